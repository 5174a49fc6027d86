!> The reference centreline of a rod and its initial director frame as functions of the arc
!> length s in [0, L] (&rod geometry, docs/user/input.md): a straight line, a circular helix, a
!> polyline, or the curve and frame of a given rest curvature and pre-twist. Pure procedures on
!> plain data; no input file, no formulation.
!>
!> Conventions:
!> - straight: phi(s) = start + s t with t the unit `direction`.
!> - helix: axis a (unit `direction`), radius R, rise per turn P, b = P / (2 pi), speed
!>   c = sqrt(R^2 + b^2) (so L = turns sqrt((2 pi R)^2 + P^2)), theta = s / c and
!>   phi(s) = start + R (cos theta - 1) u + R sin theta w + b theta a, with the radial
!>   direction u = cos(phase) n + sin(phase) (a x n), n = normal(a) (the default-d1 rule
!>   below), phase the &rod helix_phase (default 0: u = n), and w = a x u: the centreline
!>   starts at `start`, the axis is the line through start - R u along a, and the helix winds
!>   right-handed about a for P > 0 (left-handed for P < 0). Helices of one axis point p and
!>   phases phase_k, started at p + R u_k, share their axis (the wires of a strand).
!> - polyline: vertices p_1 .. p_k joined by straight segments, s the arc length along them.
!> - The frame (d1, d2, d3) has d3 = the unit tangent, d1 = the given d1 at s = 0 carried by
!>   parallel transport (the rotation-minimizing or Bishop frame: d1' has no component along
!>   d2, the frame does not twist about d3), d2 = d3 x d1. On a helix this is the Frenet frame
!>   (N, B) turned by alpha(s) = alpha_0 - tau s about the tangent, tau = b / c^2 the torsion:
!>   d1 = cos(alpha) N + sin(alpha) B. On a polyline the frame is constant on each segment and
!>   turned at a vertex by the smallest rotation taking one segment's tangent to the next (the
!>   discrete parallel transport); at a vertex itself the tangent is the bisector and the frame
!>   is turned half way.
!> - curvature: the frame and centreline integrated from the Darboux vector kappa(s) in
!>   material components, R' = R hat(kappa), phi' = d3 (rs_model_rest_curvature), from
!>   phi(0) = start, d3(0) = the unit `direction` and the given d1 at s = 0; this frame twists
!>   about d3 at the rate kappa3 (the pre-twist) and is stress-free like every other.
module rs_model_rod_geometry
    use rs_core_kinds, only: rk, pi
    use rs_core_strings, only: str, vector_text
    use rs_model_scene, only: rod_input_t, unset_real
    use rs_model_units, only: unit_in_system
    use rs_model_rest_curvature, only: rest_curvature_t, rest_curvature_table, &
        place_rest_curvature, rest_curvature_pose
    implicit none
    private

    public :: rod_geometry_t, straight_geometry, helix_geometry, polyline_geometry
    public :: set_start_director, centreline_point, centreline_tangent, centreline_frame
    public :: default_normal, helix_axis_point, rod_geometry_of, curvature_geometry
    public :: curvature_rows, centreline_text

    !> Kinds of centreline.
    integer, parameter, public :: geometry_straight = 1, geometry_helix = 2, &
        geometry_polyline = 3, geometry_curvature = 4

    !> Relative distance of s from a polyline vertex below which s is at the vertex.
    real(rk), parameter :: vertex_tolerance = 1.0e-12_rk

    !> A reference centreline, with its frame once set_start_director has given d1 at s = 0.
    type, public :: rod_geometry_t
        integer :: kind = 0
        !> Arc length L of the centreline.
        real(rk) :: length = 0.0_rk
        !> phi(0).
        real(rk) :: start(3) = 0.0_rk
        !> Straight: the unit tangent; helix: the unit axis a; curvature: the unit d3(0).
        real(rk) :: axis(3) = 0.0_rk
        !> Helix: R, b = rise / (2 pi), c = sqrt(R^2 + b^2), u and w = a x u.
        real(rk) :: radius = 0.0_rk
        real(rk) :: rise = 0.0_rk
        real(rk) :: speed = 1.0_rk
        real(rk) :: radial(3) = 0.0_rk
        real(rk) :: lateral(3) = 0.0_rk
        !> Helix: angle of d1 from the principal normal N at s = 0, about the tangent.
        real(rk) :: alpha_0 = 0.0_rk
        !> Polyline: vertices (3, k), arc length at each vertex, unit tangent of each segment.
        real(rk), allocatable :: vertices(:, :)
        real(rk), allocatable :: vertex_s(:)
        real(rk), allocatable :: tangents(:, :)
        !> Polyline: d1 on each segment (set by set_start_director).
        real(rk), allocatable :: normals(:, :)
        !> Curvature: the table of kappa(s) and its placed pieces.
        type(rest_curvature_t) :: curvature
        !> d1 at s = 0 (unit, normal to the tangent there).
        real(rk) :: d1_start(3) = 0.0_rk
    end type rod_geometry_t

contains

    !> The straight centreline start + s direction, 0 <= s <= length (direction a unit vector).
    pure function straight_geometry(start, direction, length) result(g)
        real(rk), intent(in) :: start(3), direction(3), length
        type(rod_geometry_t) :: g
        g%kind = geometry_straight
        g%start = start
        g%axis = direction
        g%length = length
    end function straight_geometry

    !> The helix of unit axis `axis`, `radius` > 0, rise per turn `pitch` and `turns` > 0 turns,
    !> starting at `start`, its start at angle `phase` (rad, default 0) about the axis from
    !> default_normal(axis) (module header).
    pure function helix_geometry(start, axis, radius, pitch, turns, phase) result(g)
        real(rk), intent(in) :: start(3), axis(3), radius, pitch, turns
        real(rk), intent(in), optional :: phase
        type(rod_geometry_t) :: g
        real(rk) :: per_turn, n(3)
        g%kind = geometry_helix
        g%start = start
        g%axis = axis
        g%radius = radius
        g%rise = pitch / (2.0_rk * pi)
        per_turn = sqrt((2.0_rk * pi * radius)**2 + pitch**2)
        g%speed = per_turn / (2.0_rk * pi)
        g%length = turns * per_turn
        n = default_normal(axis)
        g%radial = n
        ! Phase 0 keeps u = n bit for bit (the helices of scenes without helix_phase).
        if (present(phase)) then
            if (phase /= 0.0_rk) g%radial = cos(phase) * n + sin(phase) * cross(axis, n)
        end if
        g%lateral = cross(axis, g%radial)
    end function helix_geometry

    !> The polyline through the columns of `points` (3, k), k >= 2, consecutive points distinct
    !> and no segment reversing the previous one (the caller checks).
    pure function polyline_geometry(points) result(g)
        real(rk), intent(in) :: points(:, :)
        type(rod_geometry_t) :: g
        real(rk) :: segment
        integer :: j, k
        k = size(points, 2)
        g%kind = geometry_polyline
        g%vertices = points
        g%start = points(:, 1)
        allocate(g%vertex_s(k), g%tangents(3, k - 1))
        g%vertex_s(1) = 0.0_rk
        do j = 1, k - 1
            segment = norm2(points(:, j + 1) - points(:, j))
            g%tangents(:, j) = (points(:, j + 1) - points(:, j)) / segment
            g%vertex_s(j + 1) = g%vertex_s(j) + segment
        end do
        g%length = g%vertex_s(k)
        g%axis = g%tangents(:, 1)
    end function polyline_geometry

    !> The centreline of rest curvature kappa(:, j) at the rows s(j) of a table (piecewise
    !> linear; rs_model_rest_curvature, whose rules the caller checks), starting at `start`
    !> with d3 = `direction` (unit); placed with d1 = default_normal(direction) until
    !> set_start_director gives another.
    pure function curvature_geometry(start, direction, s, kappa) result(g)
        real(rk), intent(in) :: start(3), direction(3), s(:), kappa(:, :)
        type(rod_geometry_t) :: g
        g%kind = geometry_curvature
        g%start = start
        g%axis = direction
        g%length = s(size(s))
        g%curvature = rest_curvature_table(s, kappa)
        call set_start_director(g, default_normal(direction))
    end function curvature_geometry

    !> The rows (s, kappa) of a resolved curvature rod: its rest_curvature_table, or the two
    !> rows (0, kappa) and (length, kappa) of a constant rest_curvature.
    pure subroutine curvature_rows(rod, s, kappa)
        type(rod_input_t), intent(in) :: rod
        real(rk), allocatable, intent(out) :: s(:), kappa(:, :)
        real(rk), allocatable :: rows(:, :)
        integer :: n_rows
        if (rod%rest_curvature(1) /= unset_real) then
            s = [0.0_rk, rod%length]
            kappa = reshape([rod%rest_curvature, rod%rest_curvature], [3, 2])
            return
        end if
        n_rows = 0
        do while (4 * n_rows + 4 <= size(rod%rest_curvature_table))
            if (rod%rest_curvature_table(4 * n_rows + 4) == unset_real) exit
            n_rows = n_rows + 1
        end do
        rows = reshape(rod%rest_curvature_table(1:4 * n_rows), [4, n_rows])
        s = rows(1, :)
        kappa = rows(2:4, :)
    end subroutine curvature_rows

    !> Give the frame its d1 at s = 0: a unit vector normal to centreline_tangent(g, 0).
    pure subroutine set_start_director(g, d1)
        type(rod_geometry_t), intent(inout) :: g
        real(rk), intent(in) :: d1(3)
        real(rk) :: t(3), n(3), b(3)
        integer :: j
        g%d1_start = d1
        select case (g%kind)
        case (geometry_helix)
            call helix_frenet(g, 0.0_rk, t, n, b)
            g%alpha_0 = atan2(dot_product(d1, b), dot_product(d1, n))
        case (geometry_polyline)
            if (allocated(g%normals)) deallocate(g%normals)
            allocate(g%normals(3, size(g%tangents, 2)))
            g%normals(:, 1) = d1
            do j = 2, size(g%tangents, 2)
                g%normals(:, j) = minimal_rotation(g%tangents(:, j - 1), g%tangents(:, j), &
                    g%normals(:, j - 1))
            end do
        case (geometry_curvature)
            call place_rest_curvature(g%curvature, reshape([d1, cross(g%axis, d1), g%axis], &
                [3, 3]), g%start)
        end select
    end subroutine set_start_director

    !> The centreline and frame of a resolved &rod (rs_io_input_check): its geometry with its
    !> start, direction, length, helix_*, points or rest_curvature*, and d1 at s = 0.
    pure function rod_geometry_of(rod) result(g)
        type(rod_input_t), intent(in) :: rod
        type(rod_geometry_t) :: g
        real(rk), allocatable :: s(:), kappa(:, :)
        integer :: n_points
        select case (trim(rod%geometry))
        case ('curvature')
            call curvature_rows(rod, s, kappa)
            g = curvature_geometry(rod%start, rod%direction, s, kappa)
        case ('helix')
            g = helix_geometry(rod%start, rod%direction, rod%helix_radius, rod%helix_pitch, &
                rod%helix_turns, rod%helix_phase)
        case ('polyline')
            n_points = 0
            do while (3 * n_points + 3 <= size(rod%points))
                if (rod%points(3 * n_points + 3) == unset_real) exit
                n_points = n_points + 1
            end do
            g = polyline_geometry(reshape(rod%points(1:3 * n_points), [3, n_points]))
        case default
            g = straight_geometry(rod%start, rod%direction, rod%length)
        end select
        call set_start_director(g, rod%d1)
    end function rod_geometry_of

    !> phi(s).
    pure function centreline_point(g, s) result(x)
        type(rod_geometry_t), intent(in) :: g
        real(rk), intent(in) :: s
        real(rk) :: x(3)
        real(rk) :: theta, d(3, 3)
        integer :: j
        select case (g%kind)
        case (geometry_curvature)
            call rest_curvature_pose(g%curvature, s, d, x)
        case (geometry_helix)
            theta = s / g%speed
            x = g%start + g%radius * (cos(theta) - 1.0_rk) * g%radial &
                + g%radius * sin(theta) * g%lateral + g%rise * theta * g%axis
        case (geometry_polyline)
            j = segment_of(g, s)
            x = g%vertices(:, j) + (s - g%vertex_s(j)) * g%tangents(:, j)
        case default
            x = g%start + s * g%axis
        end select
    end function centreline_point

    !> The unit tangent phi'(s) (the bisector of the two segments at a polyline vertex).
    pure function centreline_tangent(g, s) result(t)
        type(rod_geometry_t), intent(in) :: g
        real(rk), intent(in) :: s
        real(rk) :: t(3)
        real(rk) :: n(3), b(3), d(3, 3), x(3)
        integer :: j
        select case (g%kind)
        case (geometry_curvature)
            call rest_curvature_pose(g%curvature, s, d, x)
            t = d(:, 3)
        case (geometry_helix)
            call helix_frenet(g, s, t, n, b)
        case (geometry_polyline)
            j = vertex_at(g, s)
            if (j > 0) then
                t = bisector(g%tangents(:, j - 1), g%tangents(:, j))
            else
                t = g%tangents(:, segment_of(g, s))
            end if
        case default
            t = g%axis
        end select
    end function centreline_tangent

    !> The frame at s, d(:, i) = d_i (module header); set_start_director must have been called.
    pure function centreline_frame(g, s) result(d)
        type(rod_geometry_t), intent(in) :: g
        real(rk), intent(in) :: s
        real(rk) :: d(3, 3)
        real(rk) :: t(3), n(3), b(3), alpha, x(3)
        integer :: j
        select case (g%kind)
        case (geometry_curvature)
            call rest_curvature_pose(g%curvature, s, d, x)
        case (geometry_helix)
            call helix_frenet(g, s, t, n, b)
            alpha = g%alpha_0 - g%rise / g%speed**2 * s
            d(:, 1) = cos(alpha) * n + sin(alpha) * b
            d(:, 3) = t
        case (geometry_polyline)
            j = vertex_at(g, s)
            if (j > 0) then
                d(:, 3) = bisector(g%tangents(:, j - 1), g%tangents(:, j))
                d(:, 1) = minimal_rotation(g%tangents(:, j - 1), d(:, 3), g%normals(:, j - 1))
            else
                j = segment_of(g, s)
                d(:, 3) = g%tangents(:, j)
                d(:, 1) = g%normals(:, j)
            end if
        case default
            d(:, 1) = g%d1_start
            d(:, 3) = g%axis
        end select
        d(:, 2) = cross(d(:, 3), d(:, 1))
    end function centreline_frame

    !> A point of the helix axis: start - R u.
    pure function helix_axis_point(g) result(x)
        type(rod_geometry_t), intent(in) :: g
        real(rk) :: x(3)
        x = g%start - g%radius * g%radial
    end function helix_axis_point

    !> The centreline of a resolved &rod in words (the --check-input plans): its kind,
    !> parameters, length and, for a helix, its axis; lengths in the &run `units`.
    function centreline_text(rod, units) result(text)
        type(rod_input_t), intent(in) :: rod
        character(len=*), intent(in) :: units
        character(len=:), allocatable :: text, m
        type(rod_geometry_t) :: geometry
        m = unit_in_system('m', units)
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
        case ('curvature')
            if (rod%rest_curvature(1) /= unset_real) then
                text = 'constant rest curvature and pre-twist (' // &
                    vector_text(rod%rest_curvature) // ') ' // unit_in_system('1/m', units)
            else
                text = 'rest curvature and pre-twist from a table of ' // &
                    str(size(geometry%curvature%s)) // ' rows, piecewise linear in s'
            end if
            text = text // ' (material d1, d2, d3) from (' // vector_text(rod%start) // &
                ') with d3 = (' // vector_text(rod%direction) // ')'
        case default
            text = 'straight from (' // vector_text(rod%start) // ') along (' // &
                vector_text(rod%direction) // ')'
        end select
        text = text // ', length ' // str(rod%length) // ' ' // m // ', d1(0) = (' // &
            vector_text(rod%d1) // ')'
    end function centreline_text

    !> A unit vector normal to the unit vector t: e_z x t normalized, or e_x when t is along
    !> e_z. The default d1 of a rod (for t along e_x: e_y) and the radial direction u of a helix.
    pure function default_normal(t) result(n)
        real(rk), intent(in) :: t(3)
        real(rk) :: n(3)
        n = [-t(2), t(1), 0.0_rk] + 0.0_rk   ! + 0 turns -0.0 into 0.0 for the echo
        if (norm2(n) < 1.0e-8_rk) then
            n = [1.0_rk, 0.0_rk, 0.0_rk]
        else
            n = n / norm2(n)
        end if
    end function default_normal

    ! Tangent T, principal normal N (towards the axis) and binormal B = T x N of the helix at s.
    pure subroutine helix_frenet(g, s, t, n, b)
        type(rod_geometry_t), intent(in) :: g
        real(rk), intent(in) :: s
        real(rk), intent(out) :: t(3), n(3), b(3)
        real(rk) :: theta
        theta = s / g%speed
        t = (-g%radius * sin(theta) * g%radial + g%radius * cos(theta) * g%lateral &
            + g%rise * g%axis) / g%speed
        n = -(cos(theta) * g%radial + sin(theta) * g%lateral)
        b = (g%rise * sin(theta) * g%radial - g%rise * cos(theta) * g%lateral &
            + g%radius * g%axis) / g%speed
    end subroutine helix_frenet

    ! Segment j of a polyline with vertex_s(j) <= s < vertex_s(j + 1) (the last one at s = L).
    pure integer function segment_of(g, s) result(j)
        type(rod_geometry_t), intent(in) :: g
        real(rk), intent(in) :: s
        integer :: n_segments
        n_segments = size(g%tangents, 2)
        j = 1
        do while (j < n_segments)
            if (s < g%vertex_s(j + 1)) exit
            j = j + 1
        end do
    end function segment_of

    ! Interior vertex j (2 .. k - 1) at arc length s, or 0.
    pure integer function vertex_at(g, s) result(vertex)
        type(rod_geometry_t), intent(in) :: g
        real(rk), intent(in) :: s
        integer :: j
        vertex = 0
        do j = 2, size(g%vertex_s) - 1
            if (abs(s - g%vertex_s(j)) <= vertex_tolerance * g%length) then
                vertex = j
                return
            end if
        end do
    end function vertex_at

    ! The unit bisector of unit vectors a and b (not opposite).
    pure function bisector(a, b) result(m)
        real(rk), intent(in) :: a(3), b(3)
        real(rk) :: m(3)
        m = (a + b) / norm2(a + b)
    end function bisector

    ! x turned by the smallest rotation taking unit a to unit b (a . b > -1), Rodrigues' form
    ! R x = (a . b) x + (a x b) x x + (a x b) ((a x b) . x) / (1 + a . b).
    pure function minimal_rotation(a, b, x) result(y)
        real(rk), intent(in) :: a(3), b(3), x(3)
        real(rk) :: y(3)
        real(rk) :: v(3), c
        v = cross(a, b)
        c = dot_product(a, b)
        y = c * x + cross(v, x) + dot_product(v, x) / (1.0_rk + c) * v
    end function minimal_rotation

    pure function cross(a, b) result(c)
        real(rk), intent(in) :: a(3), b(3)
        real(rk) :: c(3)
        c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
    end function cross

end module rs_model_rod_geometry
