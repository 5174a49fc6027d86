!> A reference centreline and frame given by their rest curvature and pre-twist as functions of
!> the arc length (&rod geometry = 'curvature'; docs/theory/rest_curvature.md): the frame
!> R = (d1, d2, d3) and the centreline r solve
!>
!>     R' = R hat(kappa(s)),   r' = R e3   (= d3),   R(0) = R0, r(0) = r0,
!>
!> with kappa = (kappa1, kappa2, kappa3) the Darboux vector in material components: kappa1 and
!> kappa2 bend about d1 and d2, kappa3 twists about d3 (the pre-twist rate). As a pose
!> H = [[R, r], [0, 1]] this is H' = H hat_se3(xi(s)) with the constant-translation twist
!> xi = (e3, kappa(s)) (rs_math_se3 order: translation first).
!>
!> kappa is piecewise linear in s between the rows (s_j, kappa_j) of a table (a constant is the
!> table of two equal rows at 0 and L; two rows at one s make a jump). On each piece the pose
!> advances by the sixth-order Magnus step of docs/theory/rest_curvature.md eq. (4), exact when
!> kappa is constant on the piece, so a constant kappa gives the closed form
!> H(s) = H0 Exp_SE3(s xi) (R0 Exp(s hat kappa), r0 + R0 T_SO3^T(s kappa) s e3) in one step.
!> Where kappa varies, the table interval is cut into pieces of length h with
!> h max(|kappa_a|, |kappa_b|, |kappa_b - kappa_a|^(1/2) / H^(1/2)) <= `piece_angle` (H the
!> interval, so both the turning and the change of kappa are resolved): the error of the
!> sixth-order step is then about 1e-14 of the length (measured in
!> tests/unit/model/test_rest_curvature.F90; 5e-13 with the turning alone at 0.03). The poses
!> at the piece starts are computed once (place_rest_curvature); a pose at any s is one Magnus
!> step from its piece's start.
!> Pure procedures on plain data.
module rs_model_rest_curvature
    use rs_core_kinds, only: rk
    use rs_math_se3, only: ad_se3, exp_se3, pose_compose
    implicit none
    private

    public :: rest_curvature_t, rest_curvature_table, place_rest_curvature, rest_curvature_pose
    public :: rest_curvature_at, magnus_twist, advance_pose

    !> Largest turning angle (rad) of one Magnus piece where kappa varies (module header).
    real(rk), parameter, public :: piece_angle = 0.02_rk

    !> The rows of the table and, once placed, the pieces with their start poses.
    type, public :: rest_curvature_t
        !> Arc length s_j of each row (non-decreasing, from 0) and kappa_j (3, rows).
        real(rk), allocatable :: s(:)
        real(rk), allocatable :: kappa(:, :)
        !> Each piece: its ends (2, pieces), kappa at its two ends (3, 2, pieces) and the
        !> frame (3, 3, pieces) and point (3, pieces) at its start.
        real(rk), allocatable :: piece_s(:, :)
        real(rk), allocatable :: piece_kappa(:, :, :)
        real(rk), allocatable :: piece_frame(:, :, :)
        real(rk), allocatable :: piece_point(:, :)
    end type rest_curvature_t

contains

    !> The table of rows (s(j), kappa(:, j)): s(1) = 0, non-decreasing, at most two rows at one
    !> s and s(last) > 0 (the caller checks).
    pure function rest_curvature_table(s, kappa) result(c)
        real(rk), intent(in) :: s(:), kappa(:, :)
        type(rest_curvature_t) :: c
        c%s = s
        c%kappa = kappa
    end function rest_curvature_table

    !> Cut the table into pieces and integrate the pose from (frame0, point0) at s = 0 to the
    !> start of every piece.
    pure subroutine place_rest_curvature(c, frame0, point0)
        type(rest_curvature_t), intent(inout) :: c
        real(rk), intent(in) :: frame0(3, 3), point0(3)
        real(rk) :: h, kappa_a(3), kappa_b(3), step(3), frame(3, 3), point(3)
        integer :: j, k, n, m, n_pieces
        n_pieces = 0
        do j = 1, size(c%s) - 1
            n_pieces = n_pieces + pieces_of(j)
        end do
        if (allocated(c%piece_s)) deallocate(c%piece_s, c%piece_kappa, c%piece_frame, c%piece_point)
        allocate(c%piece_s(2, n_pieces), c%piece_kappa(3, 2, n_pieces), &
            c%piece_frame(3, 3, n_pieces), c%piece_point(3, n_pieces))
        frame = frame0
        point = point0
        m = 0
        do j = 1, size(c%s) - 1
            n = pieces_of(j)
            if (n == 0) cycle
            h = (c%s(j + 1) - c%s(j)) / real(n, rk)
            do k = 1, n
                m = m + 1
                c%piece_s(:, m) = c%s(j) + h * [real(k - 1, rk), real(k, rk)]
                if (k == n) c%piece_s(2, m) = c%s(j + 1)
                step = (c%kappa(:, j + 1) - c%kappa(:, j)) / real(n, rk)
                kappa_a = c%kappa(:, j) + step * real(k - 1, rk)
                kappa_b = c%kappa(:, j) + step * real(k, rk)
                c%piece_kappa(:, 1, m) = kappa_a
                c%piece_kappa(:, 2, m) = kappa_b
                c%piece_frame(:, :, m) = frame
                c%piece_point(:, m) = point
                call advance_pose(frame, point, magnus_twist(kappa_a, kappa_b, &
                    c%piece_s(2, m) - c%piece_s(1, m)))
            end do
        end do
    contains
        ! Pieces of table interval j: none if it has no length (a jump), one if kappa is constant
        ! on it (exact), else enough for angles up to piece_angle (module header).
        pure integer function pieces_of(j) result(n)
            integer, intent(in) :: j
            real(rk) :: length, turning
            length = c%s(j + 1) - c%s(j)
            n = 0
            if (length <= 0.0_rk) return
            n = 1
            if (all(c%kappa(:, j + 1) == c%kappa(:, j))) return
            turning = length * max(norm2(c%kappa(:, j)), norm2(c%kappa(:, j + 1)), &
                sqrt(norm2(c%kappa(:, j + 1) - c%kappa(:, j)) / length))
            n = max(1, ceiling(turning / piece_angle))
        end function pieces_of
    end subroutine place_rest_curvature

    !> The frame (columns d1, d2, d3) and point at s (clamped to [0, L]); the table must have
    !> been placed.
    pure subroutine rest_curvature_pose(c, s, frame, point)
        type(rest_curvature_t), intent(in) :: c
        real(rk), intent(in) :: s
        real(rk), intent(out) :: frame(3, 3), point(3)
        real(rk) :: t, kappa_s(3)
        integer :: m
        m = piece_at(c, s)
        t = min(max(s, c%piece_s(1, m)), c%piece_s(2, m))
        kappa_s = c%piece_kappa(:, 1, m) + (c%piece_kappa(:, 2, m) - c%piece_kappa(:, 1, m)) * &
            (t - c%piece_s(1, m)) / (c%piece_s(2, m) - c%piece_s(1, m))
        frame = c%piece_frame(:, :, m)
        point = c%piece_point(:, m)
        call advance_pose(frame, point, magnus_twist(c%piece_kappa(:, 1, m), kappa_s, &
            t - c%piece_s(1, m)))
    end subroutine rest_curvature_pose

    !> kappa(s) of the table (at a jump: the value after it; clamped to [0, L]).
    pure function rest_curvature_at(c, s) result(kappa)
        type(rest_curvature_t), intent(in) :: c
        real(rk), intent(in) :: s
        real(rk) :: kappa(3)
        integer :: j
        kappa = c%kappa(:, size(c%s))
        do j = 1, size(c%s) - 1
            if (s < c%s(j + 1)) then
                kappa = c%kappa(:, j)
                if (c%s(j + 1) > c%s(j)) kappa = kappa + (c%kappa(:, j + 1) - c%kappa(:, j)) * &
                    (max(s, c%s(j)) - c%s(j)) / (c%s(j + 1) - c%s(j))
                return
            end if
        end do
    end function rest_curvature_at

    !> The sixth-order Magnus twist Omega of H' = H hat_se3(e3, kappa(s)) over a step of length h
    !> with kappa linear from kappa_a to kappa_b (docs/theory/rest_curvature.md eqs. (3)-(4)):
    !> H(h) = H(0) Exp_SE3(Omega) + O(h^7). With a1 = h (e3, (kappa_a + kappa_b) / 2) (the
    !> integral of xi) and a2 = h (0, kappa_b - kappa_a) (the three-point Gauss moment; the
    !> second difference of a linear kappa vanishes), C1 = -[a1, a2], C2 = [a1, C1] / 60 and
    !> Omega = a1 - [-20 a1 + C1, a2 + C2] / 240, [x, y] = ad_x y. Omega = h xi, exactly, when
    !> kappa_a = kappa_b.
    pure function magnus_twist(kappa_a, kappa_b, h) result(omega)
        real(rk), intent(in) :: kappa_a(3), kappa_b(3), h
        real(rk) :: omega(6)
        real(rk) :: a1(6), a2(6), c1(6), c2(6)
        a1 = h * [0.0_rk, 0.0_rk, 1.0_rk, 0.5_rk * (kappa_a + kappa_b)]
        if (all(kappa_a == kappa_b)) then
            omega = a1
            return
        end if
        a2 = h * [0.0_rk, 0.0_rk, 0.0_rk, kappa_b - kappa_a]
        c1 = -matmul(ad_se3(a1), a2)
        c2 = matmul(ad_se3(a1), c1) / 60.0_rk
        omega = a1 - matmul(ad_se3(-20.0_rk * a1 + c1), a2 + c2) / 240.0_rk
    end function magnus_twist

    !> (frame, point) <- (frame, point) Exp_SE3(omega): one step of the pose along the rod.
    pure subroutine advance_pose(frame, point, omega)
        real(rk), intent(inout) :: frame(3, 3), point(3)
        real(rk), intent(in) :: omega(6)
        real(rk) :: a(3, 3), r(3), frame_new(3, 3), point_new(3)
        call exp_se3(omega, a, r)
        call pose_compose(frame, point, a, r, frame_new, point_new)
        frame = frame_new
        point = point_new
    end subroutine advance_pose

    ! The piece whose start is the last one at or before s (the first for s < 0).
    pure integer function piece_at(c, s) result(m)
        type(rest_curvature_t), intent(in) :: c
        real(rk), intent(in) :: s
        integer :: low, high, middle
        low = 1
        high = size(c%piece_s, 2)
        do while (low < high)
            middle = (low + high + 1) / 2
            if (c%piece_s(1, middle) <= s) then
                low = middle
            else
                high = middle - 1
            end if
        end do
        m = low
    end function piece_at

end module rs_model_rest_curvature
