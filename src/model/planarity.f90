!> Whether a set of rods (e.g. those tied together by joints) and everything acting on them lie
!> in one plane, so that a planar formulation can run them (DESIGN.md §4, `formulation =
!> 'auto'`), and the plane's coordinates: planar formulations work in (x, y, theta) with
!> x = (p - origin) . e1, y = (p - origin) . e2 and theta the angle of a vector from e1 towards
!> e2. Pure procedures on plain scene data (STYLE.md item 2); no formulation.
!>
!> A scene is planar when, for the rods and the loads that apply to them (a gravity load with
!> rod = '' applies to every rod):
!> - in the plane: each rod's direction (straight rods only: a helix or polyline is a curved
!>   reference, never planar here), its initial velocity, the forces of its end and distributed
!>   loads, the gravity accelerations, and the rods' start points (all in one plane);
!> - along the normal: the moments of the loads and the initial angular velocities;
!> - each rod's resolved d1 is along or perpendicular to the normal, so that one of d1, d2 is
!>   the normal and the cross-section turns in the plane.
!>
!> The normal is the first nonzero moment or angular velocity; else the cross product of two
!> non-parallel in-plane vectors (of all such pairs the one whose plane violates the fewest
!> conditions, then the least parallel pair, then the first: any pair gives the same plane when
!> the scene is planar, and otherwise the reason names what most likely leaves the intended
!> plane); else (all in-plane vectors parallel) the first of e_z, e_y, e_x and d1, d2 of the
!> first rod that is perpendicular to them all and meets the director rule. Its sign makes
!> n . e_z > 0, else n . e_y > 0, else n . e_x > 0. The origin is
!> (n . start of the first rod) n, e1 the normalized projection of e_x onto the plane (of e_y
!> when e_x is nearly normal to it) and e2 = n x e1: a scene in the xy-plane has e1 = e_x,
!> e2 = e_y, n = e_z and planar coordinates equal to x and y. Every condition is then verified
!> to the relative tolerance `planarity_tolerance`, and the first one violated is the reason.
module rs_model_planarity
    use rs_core_kinds, only: rk
    use rs_core_strings, only: str, vector_text
    use rs_model_scene, only: scene_t, unset_real, coordinate_axis
    use rs_model_support, only: end_hold_t
    implicit none
    private

    public :: plane_of_rods, point_in_plane, vector_in_plane, point_from_plane, vector_from_plane
    public :: angle_in_plane, plane_text, cross, planar_coordinate_axis, planar_held

    !> Relative tolerance of every planarity condition (a component along the normal of at most
    !> this times the vector's norm, or the scene's length scale for points, counts as zero).
    real(rk), parameter, public :: planarity_tolerance = 1.0e-12_rk

    !> A plane with a right-handed orthonormal basis: e1 x e2 = normal.
    type, public :: plane_t
        !> True if the rods and everything acting on them lie in this plane.
        logical :: found = .false.
        real(rk) :: origin(3) = 0.0_rk
        real(rk) :: e1(3) = 0.0_rk
        real(rk) :: e2(3) = 0.0_rk
        real(rk) :: normal(3) = 0.0_rk
        !> Why the rods are not planar: the first violated condition, naming the rod or load,
        !> its input line and the vector ('' when found).
        character(len=:), allocatable :: reason
    end type plane_t

    !> Kinds of condition.
    integer, parameter :: in_plane = 1, point_in = 2, along_normal = 3, director = 4

    !> One condition on one vector of the scene.
    type :: condition_t
        integer :: kind = 0
        real(rk) :: v(3) = 0.0_rk
        !> Length scale of a point condition (the distance from the plane is compared to it).
        real(rk) :: scale = 0.0_rk
        !> What the vector is, e.g. "load 3 (line 41): force".
        character(len=:), allocatable :: label
    end type condition_t

    real(rk), parameter :: e_x(3) = [1.0_rk, 0.0_rk, 0.0_rk]
    real(rk), parameter :: e_y(3) = [0.0_rk, 1.0_rk, 0.0_rk]
    real(rk), parameter :: e_z(3) = [0.0_rk, 0.0_rk, 1.0_rk]

contains

    !> The plane of rods `rods` (indices into scene%rods, resolved: start, direction, d1 and
    !> length set) and of the loads acting on them; plane%found is false, with plane%reason,
    !> if there is none (module header).
    pure function plane_of_rods(scene, rods) result(plane)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:)
        type(plane_t) :: plane
        type(condition_t), allocatable :: conditions(:)
        real(rk) :: n(3), p(3)
        character(len=:), allocatable :: source, failure
        integer :: k

        plane%reason = ''
        if (size(rods) == 0) then
            plane%reason = 'no rods'
            return
        end if
        do k = 1, size(rods)
            associate (rod => scene%rods(rods(k)))
                if (trim(rod%geometry) /= 'straight') then
                    plane%reason = rod_label(scene, rods(k)) // ': curved reference (geometry ''' // &
                        trim(rod%geometry) // '''); the planar formulations take straight rods only'
                    return
                end if
                if (any(rod%start == unset_real) .or. any(rod%direction == unset_real) .or. &
                        any(rod%d1 == unset_real)) then
                    plane%reason = rod_label(scene, rods(k)) // ': not resolved (start, ' // &
                        'direction or d1 unknown)'
                    return
                end if
            end associate
        end do
        conditions = scene_conditions(scene, rods)
        call choose_normal(scene, rods, conditions, n, source)
        if (all(n == 0.0_rk)) then
            plane%reason = 'no plane contains the rods and their loads'
            return
        end if
        ! Sign: n . e_z > 0, else n . e_y > 0, else n . e_x > 0 (components at round-off
        ! level count as zero); adding 0 turns -0.0 into 0.0.
        if (abs(n(3)) > planarity_tolerance) then
            if (n(3) < 0.0_rk) n = -n
        else if (abs(n(2)) > planarity_tolerance) then
            if (n(2) < 0.0_rk) n = -n
        else if (n(1) < 0.0_rk) then
            n = -n
        end if
        n = n + 0.0_rk
        plane%normal = n
        plane%origin = dot_product(n, scene%rods(rods(1))%start) * n + 0.0_rk
        p = e_x - dot_product(e_x, n) * n
        if (norm2(p) < 1.0e-6_rk) p = e_y - dot_product(e_y, n) * n
        plane%e1 = p / norm2(p) + 0.0_rk
        plane%e2 = cross(n, plane%e1) + 0.0_rk
        do k = 1, size(conditions)
            failure = violation(conditions(k), plane)
            if (len(failure) > 0) then
                plane%reason = failure // ' (the plane follows from ' // source // ')'
                return
            end if
        end do
        plane%found = .true.
    end function plane_of_rods

    !> Planar coordinates (x, y) of point `p`: ((p - origin) . e1, (p - origin) . e2).
    pure function point_in_plane(plane, p) result(xy)
        type(plane_t), intent(in) :: plane
        real(rk), intent(in) :: p(3)
        real(rk) :: xy(2)
        xy = [dot_product(p - plane%origin, plane%e1), dot_product(p - plane%origin, plane%e2)]
    end function point_in_plane

    !> Planar components (v . e1, v . e2) of vector `v`.
    pure function vector_in_plane(plane, v) result(xy)
        type(plane_t), intent(in) :: plane
        real(rk), intent(in) :: v(3)
        real(rk) :: xy(2)
        xy = [dot_product(v, plane%e1), dot_product(v, plane%e2)]
    end function vector_in_plane

    !> 1 or 2 if `v` lies along e1 or e2 of the plane (its other components below 1e-12 |v|),
    !> else 0: the coordinate a sliding end of a planar rod keeps free.
    pure integer function planar_coordinate_axis(plane, v) result(i)
        type(plane_t), intent(in) :: plane
        real(rk), intent(in) :: v(3)
        real(rk) :: c(3)
        c = [dot_product(v, plane%e1), dot_product(v, plane%e2), dot_product(v, plane%normal)]
        i = coordinate_axis(c)
        if (i == 3) i = 0
    end function planar_coordinate_axis

    !> A support's hold (rs_model_support) as held planar coordinates (x, y, theta): with E =
    !> [e1 e2], the in-plane motion E u keeps P E u = 0 exactly when Q u = 0, Q = E^T P E
    !> (P the hold's projector; Q is positive semidefinite). Q = 0: nothing in the plane is
    !> held (a roller on a plane parallel to the scene's); rank 2: x and y; rank 1: the one
    !> planar coordinate Q holds, which must be x or y (Q diagonal), else `ok` is false (an
    !> oblique direction cannot be held by eliminating a coordinate). theta is held with the
    !> rotation; the twist alone (about the rod's in-plane axis, where a planar rod has no
    !> torsion) is refused: `ok` is false (rs_model_support's twist_hold_refusal).
    pure subroutine planar_held(plane, hold, held, ok)
        type(plane_t), intent(in) :: plane
        type(end_hold_t), intent(in) :: hold
        logical, intent(out) :: held(3)
        logical, intent(out) :: ok
        real(rk) :: e(3, 2), q(2, 2), trace, determinant
        e(:, 1) = plane%e1
        e(:, 2) = plane%e2
        q = matmul(transpose(e), matmul(hold%position, e))
        trace = q(1, 1) + q(2, 2)
        determinant = q(1, 1) * q(2, 2) - q(1, 2) * q(2, 1)
        ok = .true.
        held(1:2) = .false.
        if (trace <= planarity_tolerance) then
            continue
        else if (abs(determinant) > planarity_tolerance * trace**2) then
            held(1:2) = .true.
        else if (abs(q(1, 2)) <= planarity_tolerance * trace) then
            held(1) = q(1, 1) > planarity_tolerance * trace
            held(2) = q(2, 2) > planarity_tolerance * trace
        else
            ok = .false.
        end if
        held(3) = hold%rotation
        if (hold%twist) ok = .false.
    end subroutine planar_held

    !> The point origin + x e1 + y e2 of planar coordinates `xy`.
    pure function point_from_plane(plane, xy) result(p)
        type(plane_t), intent(in) :: plane
        real(rk), intent(in) :: xy(2)
        real(rk) :: p(3)
        p = plane%origin + xy(1) * plane%e1 + xy(2) * plane%e2
    end function point_from_plane

    !> The vector x e1 + y e2 of planar components `xy`.
    pure function vector_from_plane(plane, xy) result(v)
        type(plane_t), intent(in) :: plane
        real(rk), intent(in) :: xy(2)
        real(rk) :: v(3)
        v = xy(1) * plane%e1 + xy(2) * plane%e2
    end function vector_from_plane

    !> Angle of `t` in the plane, atan2(t . e2, t . e1), in (-pi, pi]: the planar rotation
    !> angle theta of a rod whose tangent is t.
    pure real(rk) function angle_in_plane(plane, t)
        type(plane_t), intent(in) :: plane
        real(rk), intent(in) :: t(3)
        angle_in_plane = atan2(dot_product(t, plane%e2), dot_product(t, plane%e1))
    end function angle_in_plane

    !> "the plane through (o) with normal (n)", for messages and the plan.
    pure function plane_text(plane) result(text)
        type(plane_t), intent(in) :: plane
        character(len=:), allocatable :: text
        text = 'the plane through (' // vector_text(plane%origin) // ') with normal (' // &
            vector_text(plane%normal) // ')'
    end function plane_text

    ! --- conditions ---------------------------------------------------------------------------

    !> Every condition of the module header on rods `rods` and their loads, in the order they
    !> are verified: per rod its direction, start, d1, velocity and angular velocity; then per
    !> load (file order) its force, moment and gravity acceleration. Zero vectors are left out.
    pure function scene_conditions(scene, rods) result(conditions)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:)
        type(condition_t), allocatable :: conditions(:)
        real(rk) :: scale
        integer :: k, j, n
        allocate(conditions(5 * size(rods) + 3 * size(scene%loads)))
        n = 0
        ! Points are compared with the scene's size (rod lengths and coordinates), so that
        ! round-off in large coordinates does not count as leaving the plane.
        scale = 0.0_rk
        do k = 1, size(rods)
            associate (rod => scene%rods(rods(k)))
                scale = max(scale, norm2(rod%start))
                if (rod%length /= unset_real) scale = max(scale, rod%length)
            end associate
        end do
        do k = 1, size(rods)
            associate (rod => scene%rods(rods(k)))
                call add(conditions, n, in_plane, rod%direction, scale, &
                    rod_label(scene, rods(k)) // ': direction')
                if (k > 1) call add(conditions, n, point_in, rod%start, scale, &
                    rod_label(scene, rods(k)) // ': start')
                call add(conditions, n, director, rod%d1, scale, rod_label(scene, rods(k)) // ': d1')
                call add(conditions, n, in_plane, rod%velocity, scale, &
                    rod_label(scene, rods(k)) // ': velocity')
                call add(conditions, n, along_normal, rod%angular_velocity, scale, &
                    rod_label(scene, rods(k)) // ': angular_velocity')
            end associate
        end do
        do j = 1, size(scene%loads)
            if (.not. applies(scene, j, rods)) cycle
            associate (load => scene%loads(j))
                if (trim(load%where) == 'gravity') then
                    call add(conditions, n, in_plane, load%acceleration, scale, &
                        load_label(scene, j) // ': gravity acceleration')
                else
                    call add(conditions, n, in_plane, load%force, scale, load_label(scene, j) // ': force')
                    call add(conditions, n, along_normal, load%moment, scale, &
                        load_label(scene, j) // ': moment')
                end if
            end associate
        end do
        conditions = conditions(1:n)
    end function scene_conditions

    !> Append condition (kind, v, scale, label) as number n + 1 of `conditions` (zero vectors
    !> hold trivially and are left out, except points).
    pure subroutine add(conditions, n, kind, v, scale, label)
        type(condition_t), intent(inout) :: conditions(:)
        integer, intent(inout) :: n
        integer, intent(in) :: kind
        real(rk), intent(in) :: v(3), scale
        character(len=*), intent(in) :: label
        if (kind /= point_in .and. all(v == 0.0_rk)) return
        n = n + 1
        conditions(n)%kind = kind
        conditions(n)%v = v
        conditions(n)%scale = scale
        conditions(n)%label = label
    end subroutine add

    !> True if load `j` acts on one of rods `rods` (a gravity load without rod acts on all).
    pure logical function applies(scene, j, rods)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: j, rods(:)
        integer :: k
        associate (load => scene%loads(j))
            applies = len_trim(load%rod) == 0 .and. trim(load%where) == 'gravity'
            do k = 1, size(rods)
                if (applies) exit
                applies = trim(load%rod) == trim(scene%rods(rods(k))%name)
            end do
        end associate
    end function applies

    !> The unit normal (module header) and what it follows from; n = 0 if none can be found.
    pure subroutine choose_normal(scene, rods, conditions, n, source)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:)
        type(condition_t), intent(in) :: conditions(:)
        real(rk), intent(out) :: n(3)
        character(len=:), allocatable, intent(out) :: source
        real(rk), allocatable :: vectors(:, :)
        real(rk) :: candidates(3, 5), c(3), best, sine, d2(3)
        character(len=:), allocatable :: labels(:)
        character(len=32) :: candidate_names(5)
        integer :: k, a, b, n_vectors, pass, fewest, failed

        n = 0.0_rk
        source = ''
        do k = 1, size(conditions)
            if (conditions(k)%kind /= along_normal) cycle
            n = conditions(k)%v / norm2(conditions(k)%v)
            source = conditions(k)%label
            return
        end do
        ! In-plane vectors: the in-plane conditions and the offsets of the starts.
        allocate(vectors(3, size(conditions)))
        allocate(character(len=max_label(conditions)) :: labels(size(conditions)))
        n_vectors = 0
        do k = 1, size(conditions)
            select case (conditions(k)%kind)
            case (in_plane)
                c = conditions(k)%v
            case (point_in)
                c = conditions(k)%v - scene%rods(rods(1))%start
                ! Starts that coincide to round-off span no direction.
                if (norm2(c) <= planarity_tolerance * conditions(k)%scale) cycle
            case default
                cycle
            end select
            n_vectors = n_vectors + 1
            vectors(:, n_vectors) = c
            labels(n_vectors) = conditions(k)%label
        end do
        best = 0.0_rk
        fewest = huge(1)
        do a = 1, n_vectors
            do b = a + 1, n_vectors
                c = cross(vectors(:, a), vectors(:, b))
                sine = norm2(c) / (norm2(vectors(:, a)) * norm2(vectors(:, b)))
                if (sine <= planarity_tolerance) cycle
                failed = count_violations(c / norm2(c))
                if (failed < fewest .or. (failed == fewest .and. sine > best)) then
                    fewest = failed
                    best = sine
                    n = c / norm2(c)
                    source = trim(labels(a)) // ' and ' // trim(labels(b))
                end if
            end do
        end do
        if (fewest < huge(1)) return
        ! All in-plane vectors are parallel: a normal perpendicular to them that also meets the
        ! director rule, or failing that one perpendicular to them (the director rule then
        ! names the rod that fails).
        n = 0.0_rk
        associate (first => scene%rods(rods(1)))
            d2 = cross(first%direction, first%d1)
            candidates = reshape([e_z, e_y, e_x, first%d1 / norm2(first%d1), d2 / norm2(d2)], [3, 5])
            candidate_names(1:3) = [character(len=32) :: 'e_z', 'e_y', 'e_x']
            candidate_names(4) = 'd1 of rod ''' // trim(first%name) // ''''
            candidate_names(5) = 'd2 of rod ''' // trim(first%name) // ''''
        end associate
        do pass = 1, 2
            do k = 1, 5
                c = candidates(:, k)
                if (.not. perpendicular_to_all(c)) cycle
                if (pass == 1 .and. .not. directors_fit(c)) cycle
                n = c
                source = trim(candidate_names(k)) // ', normal to every in-plane vector'
                return
            end do
        end do
    contains
        !> Number of conditions violated in the plane of unit normal c through the first start.
        pure integer function count_violations(c)
            real(rk), intent(in) :: c(3)
            type(plane_t) :: trial
            integer :: j
            trial%normal = c
            trial%origin = dot_product(c, scene%rods(rods(1))%start) * c
            count_violations = 0
            do j = 1, size(conditions)
                if (.not. holds(conditions(j), trial)) count_violations = count_violations + 1
            end do
        end function count_violations

        pure logical function perpendicular_to_all(c)
            real(rk), intent(in) :: c(3)
            integer :: j
            perpendicular_to_all = .true.
            do j = 1, n_vectors
                if (abs(dot_product(vectors(:, j), c)) > planarity_tolerance * norm2(vectors(:, j))) then
                    perpendicular_to_all = .false.
                    return
                end if
            end do
        end function perpendicular_to_all

        pure logical function directors_fit(c)
            real(rk), intent(in) :: c(3)
            integer :: j
            directors_fit = .true.
            do j = 1, size(conditions)
                if (conditions(j)%kind /= director) cycle
                if (.not. director_fits(conditions(j)%v, c)) then
                    directors_fit = .false.
                    return
                end if
            end do
        end function directors_fit
    end subroutine choose_normal

    pure integer function max_label(conditions)
        type(condition_t), intent(in) :: conditions(:)
        integer :: k
        max_label = 1
        do k = 1, size(conditions)
            max_label = max(max_label, len(conditions(k)%label))
        end do
    end function max_label

    !> d1 along or perpendicular to the unit normal n.
    pure logical function director_fits(d1, n)
        real(rk), intent(in) :: d1(3), n(3)
        director_fits = norm2(cross(d1, n)) <= planarity_tolerance * norm2(d1) .or. &
            abs(dot_product(d1, n)) <= planarity_tolerance * norm2(d1)
    end function director_fits

    !> True if `condition` holds in `plane` (its normal and origin), to planarity_tolerance.
    pure logical function holds(condition, plane)
        type(condition_t), intent(in) :: condition
        type(plane_t), intent(in) :: plane
        associate (v => condition%v, n => plane%normal)
            select case (condition%kind)
            case (in_plane)
                holds = abs(dot_product(v, n)) <= planarity_tolerance * norm2(v)
            case (point_in)
                holds = abs(dot_product(v - plane%origin, n)) <= planarity_tolerance * condition%scale
            case (along_normal)
                holds = norm2(cross(v, n)) <= planarity_tolerance * norm2(v)
            case (director)
                holds = director_fits(v, n)
            case default
                holds = .true.
            end select
        end associate
    end function holds

    !> '' if `condition` holds in `plane`, else what is wrong.
    pure function violation(condition, plane) result(text)
        type(condition_t), intent(in) :: condition
        type(plane_t), intent(in) :: plane
        character(len=:), allocatable :: text
        character(len=:), allocatable :: given, normal
        text = ''
        if (holds(condition, plane)) return
        given = condition%label // ' (' // vector_text(condition%v) // ')'
        normal = ' the plane normal (' // vector_text(plane%normal) // ')'
        select case (condition%kind)
        case (in_plane)
            text = given // ' has a component along' // normal
        case (point_in)
            text = given // ' lies off ' // plane_text(plane) // ' (distance ' // &
                str(dot_product(condition%v - plane%origin, plane%normal)) // ')'
        case (along_normal)
            text = given // ' is not along' // normal
        case (director)
            text = given // ' is neither along nor perpendicular to' // normal // &
                ' (one of d1, d2 must be the normal)'
        end select
    end function violation

    pure function rod_label(scene, i) result(text)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i
        character(len=:), allocatable :: text
        text = 'rod ''' // trim(scene%rods(i)%name) // '''' // line_text(scene%rods(i)%input_line)
    end function rod_label

    pure function load_label(scene, j) result(text)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: j
        character(len=:), allocatable :: text
        text = 'load ' // str(j) // line_text(scene%loads(j)%input_line)
    end function load_label

    pure function line_text(line) result(text)
        integer, intent(in) :: line
        character(len=:), allocatable :: text
        text = ''
        if (line > 0) text = ' (line ' // str(line) // ')'
    end function line_text

    !> a x b.
    pure function cross(a, b) result(c)
        real(rk), intent(in) :: a(3), b(3)
        real(rk) :: c(3)
        c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
    end function cross

end module rs_model_planarity
