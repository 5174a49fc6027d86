#include "rs_assert.h"
!> Unit tests of rs_contact_grid, the broad phase of rod-rod contact (DESIGN.md §5). The grid's
!> candidates are compared with a brute-force O(M^2) box-overlap search computed here, and with
!> brute-force segment-segment distances (every pair within contact distance must be a
!> candidate); then the skip rule, self contact of a helix, determinism and order, run time at
!> 10^4 and 4 x 10^4 segments (reported, not asserted) and degenerate inputs.
module rs_test_contact_grid
    use, intrinsic :: iso_fortran_env, only: output_unit
    use rs_core_kinds, only: rk, pi
    use rs_core_timer, only: wall_time
    use rs_test_random, only: set_random_seed, random_unit_vector, uniform
    use rs_test_assert, only: run_test, assert_true, assert_equal
    use rs_contact_grid, only: contact_grid_t, candidate_pairs
    implicit none
    private

    public :: run_all_tests

contains

    subroutine run_all_tests()
        call set_random_seed(1009, 17)
        call run_test('random_equals_brute_force', test_random_equals_brute_force)
        call run_test('far_from_origin_and_sparse', test_far_from_origin_and_sparse)
        call run_test('skip_rule_on_one_rod', test_skip_rule_on_one_rod)
        call run_test('helix_self_contact', test_helix_self_contact)
        call run_test('deterministic_and_sorted', test_deterministic_and_sorted)
        call run_test('large_scenes_scale', test_large_scenes_scale)
        call run_test('degenerate_inputs', test_degenerate_inputs)
    end subroutine run_all_tests

    !> m random segments with centres uniform in [0, side]^3, random directions, lengths uniform
    !> in [0, max_length], radii uniform in [r_min, r_max]; rods of per_rod consecutive segments.
    subroutine random_scene(m, side, max_length, r_min, r_max, per_rod, ends, rod, index, radius)
        integer, intent(in) :: m, per_rod
        real(rk), intent(in) :: side, max_length, r_min, r_max
        real(rk), allocatable, intent(out) :: ends(:, :, :), radius(:)
        integer, allocatable, intent(out) :: rod(:), index(:)
        real(rk) :: centre(3), half(3)
        integer :: s
        allocate(ends(3, 2, m), radius(m), rod(m), index(m))
        do s = 1, m
            call random_number(centre)
            centre = side * centre
            half = 0.5_rk * uniform(0.0_rk, max_length) * random_unit_vector()
            ends(:, 1, s) = centre - half
            ends(:, 2, s) = centre + half
            radius(s) = uniform(r_min, r_max)
            rod(s) = (s - 1) / per_rod + 1
            index(s) = mod(s - 1, per_rod) + 1
        end do
    end subroutine random_scene

    !> Every pair a < b whose inflated boxes overlap, minus the skipped neighbours: O(M^2).
    subroutine brute_force_pairs(ends, rod, index, radius, margin, skip, pairs, n)
        real(rk), intent(in) :: ends(:, :, :), radius(:), margin
        integer, intent(in) :: rod(:), index(:), skip
        integer, allocatable, intent(out) :: pairs(:, :)
        integer, intent(out) :: n
        real(rk), allocatable :: lo(:, :), hi(:, :)
        integer, allocatable :: grown(:, :)
        integer :: m, a, b
        m = size(ends, 3)
        allocate(lo(3, m), hi(3, m), pairs(2, 16))
        do a = 1, m
            lo(:, a) = min(ends(:, 1, a), ends(:, 2, a)) - (radius(a) + 0.5_rk * margin)
            hi(:, a) = max(ends(:, 1, a), ends(:, 2, a)) + (radius(a) + 0.5_rk * margin)
        end do
        n = 0
        do a = 1, m
            do b = a + 1, m
                if (rod(a) == rod(b) .and. abs(index(a) - index(b)) <= skip) cycle
                if (any(lo(:, a) > hi(:, b)) .or. any(lo(:, b) > hi(:, a))) cycle
                if (n == size(pairs, 2)) then
                    allocate(grown(2, 2 * n))
                    grown(:, 1:n) = pairs(:, 1:n)
                    call move_alloc(grown, pairs)
                end if
                n = n + 1
                pairs(:, n) = [a, b]
            end do
        end do
    end subroutine brute_force_pairs

    !> Distance between segments p1-q1 and p2-q2 (closest points by clamped parameters, after
    !> Ericson, Real-Time Collision Detection §5.1.9).
    pure real(rk) function segment_distance(p1, q1, p2, q2) result(dist)
        real(rk), intent(in) :: p1(3), q1(3), p2(3), q2(3)
        real(rk) :: d1(3), d2(3), r(3), a, b, c, e, f, denom, s, t
        d1 = q1 - p1
        d2 = q2 - p2
        r = p1 - p2
        a = dot_product(d1, d1)
        e = dot_product(d2, d2)
        f = dot_product(d2, r)
        if (a <= tiny(a) .and. e <= tiny(e)) then
            s = 0.0_rk
            t = 0.0_rk
        else if (a <= tiny(a)) then
            s = 0.0_rk
            t = clamp01(f / e)
        else
            c = dot_product(d1, r)
            if (e <= tiny(e)) then
                t = 0.0_rk
                s = clamp01(-c / a)
            else
                b = dot_product(d1, d2)
                denom = a * e - b * b
                s = 0.0_rk
                if (denom > 0.0_rk) s = clamp01((b * f - c * e) / denom)
                t = (b * s + f) / e
                if (t < 0.0_rk) then
                    t = 0.0_rk
                    s = clamp01(-c / a)
                else if (t > 1.0_rk) then
                    t = 1.0_rk
                    s = clamp01((b - c) / a)
                end if
            end if
        end if
        dist = norm2(p1 + s * d1 - p2 - t * d2)
    end function segment_distance

    pure real(rk) function clamp01(x)
        real(rk), intent(in) :: x
        clamp01 = min(max(x, 0.0_rk), 1.0_rk)
    end function clamp01

    !> Pairs a < b, strictly increasing in lexicographic order.
    pure logical function strictly_sorted(pairs, n)
        integer, intent(in) :: pairs(:, :), n
        integer :: k
        strictly_sorted = all(pairs(1, 1:n) < pairs(2, 1:n))
        do k = 2, n
            if (pairs(1, k) < pairs(1, k - 1)) strictly_sorted = .false.
            if (pairs(1, k) == pairs(1, k - 1) .and. pairs(2, k) <= pairs(2, k - 1)) then
                strictly_sorted = .false.
            end if
        end do
    end function strictly_sorted

    !> Whether the first n columns of two pair lists are the same list.
    pure logical function same_pairs(p, n, q, nq)
        integer, intent(in) :: p(:, :), n, q(:, :), nq
        same_pairs = n == nq
        if (same_pairs .and. n > 0) same_pairs = all(p(:, 1:n) == q(:, 1:n))
    end function same_pairs

    !> Number of pairs a < b, not skipped, within contact distance radius(a) + radius(b) + margin
    !> that are missing from the candidates; also returns how many such pairs there are.
    subroutine missing_contacts(ends, rod, index, radius, margin, skip, pairs, n, n_close, &
                                n_missing)
        real(rk), intent(in) :: ends(:, :, :), radius(:), margin
        integer, intent(in) :: rod(:), index(:), skip, pairs(:, :), n
        integer, intent(out) :: n_close, n_missing
        logical, allocatable :: is_candidate(:, :)
        integer :: m, a, b, k
        m = size(ends, 3)
        allocate(is_candidate(m, m))
        is_candidate = .false.
        do k = 1, n
            is_candidate(pairs(1, k), pairs(2, k)) = .true.
        end do
        n_close = 0
        n_missing = 0
        do a = 1, m
            do b = a + 1, m
                if (rod(a) == rod(b) .and. abs(index(a) - index(b)) <= skip) cycle
                if (segment_distance(ends(:, 1, a), ends(:, 2, a), ends(:, 1, b), ends(:, 2, b)) &
                    > radius(a) + radius(b) + margin) cycle
                n_close = n_close + 1
                if (.not. is_candidate(a, b)) n_missing = n_missing + 1
            end do
        end do
    end subroutine missing_contacts

    ! (1) Several densities and margins: the candidates are exactly the brute-force box-overlap
    ! pairs, and include every pair within contact distance.
    subroutine test_random_equals_brute_force()
        integer, parameter :: sizes(3) = [100, 400, 1000]
        real(rk), parameter :: margins(3) = [0.0_rk, 0.01_rk, 0.05_rk]
        type(contact_grid_t) :: grid
        real(rk), allocatable :: ends(:, :, :), radius(:)
        integer, allocatable :: rod(:), index(:), expected(:, :), pairs(:, :)
        integer :: i, j, n, n_expected, n_close, n_missing, total_close
        character(len=80) :: label
        logical :: ok
        total_close = 0
        call grid%init()
        do i = 1, size(sizes)
            call random_scene(sizes(i), 1.0_rk, 0.08_rk, 0.002_rk, 0.01_rk, 20, ends, rod, index, &
                radius)
            do j = 1, size(margins)
                write(label, '(a,i0,a,f4.2)') 'M = ', sizes(i), ', margin = ', margins(j)
                call grid%build(ends, rod, index, radius, margins(j), 1)
                call grid%get_pairs(pairs, n)
                call brute_force_pairs(ends, rod, index, radius, margins(j), 1, expected, &
                    n_expected)
                CHECK_EQUAL(n, n_expected, trim(label) // ': number of candidates')
                ok = same_pairs(pairs, n, expected, n_expected)
                CHECK_TRUE(ok, trim(label) // ': candidates')
                ok = grid%n_registrations() <= 8 * sizes(i)
                CHECK_TRUE(ok, trim(label) // ': <= 8 cells a box')
                call missing_contacts(ends, rod, index, radius, margins(j), 1, pairs, n, n_close, &
                    n_missing)
                CHECK_EQUAL(n_missing, 0, trim(label) // ': pairs within contact distance missed')
                total_close = total_close + n_close
                ! Other cell sizes (a small one is raised to 1/16 of the largest box side).
                call grid%build(ends, rod, index, radius, margins(j), 1, cell_size=0.001_rk)
                call grid%get_pairs(pairs, n)
                ok = same_pairs(pairs, n, expected, n_expected)
                CHECK_TRUE(ok, trim(label) // ': tiny cells')
                call grid%build(ends, rod, index, radius, margins(j), 1, cell_size=0.3_rk)
                call grid%get_pairs(pairs, n)
                ok = same_pairs(pairs, n, expected, n_expected)
                CHECK_TRUE(ok, trim(label) // ': large cells')
            end do
        end do
        CHECK_TRUE(total_close > 100, 'the random scenes have pairs within contact distance')
        call grid%free()
    end subroutine test_random_equals_brute_force

    ! Coordinates far from the origin and two clusters far apart: same as brute force, and the
    ! number of cells follows the segments, not the empty space between them.
    subroutine test_far_from_origin_and_sparse()
        type(contact_grid_t) :: grid
        real(rk), allocatable :: ends(:, :, :), radius(:)
        integer, allocatable :: rod(:), index(:), expected(:, :), pairs(:, :)
        integer :: n, n_expected
        call random_scene(300, 1.0_rk, 0.1_rk, 0.005_rk, 0.01_rk, 30, ends, rod, index, radius)
        ends = ends + 1.0e9_rk
        call grid%build(ends, rod, index, radius, 0.02_rk, 2)
        call grid%get_pairs(pairs, n)
        call brute_force_pairs(ends, rod, index, radius, 0.02_rk, 2, expected, n_expected)
        CHECK_TRUE(n_expected > 0, 'the scene at 1e9 has box-overlap pairs')
        CHECK_TRUE(same_pairs(pairs, n, expected, n_expected), 'scene at 1e9: candidates')
        ! Half of the segments moved 1e8 away along a diagonal.
        ends(:, :, 151:) = ends(:, :, 151:) + 1.0e8_rk
        call grid%build(ends, rod, index, radius, 0.02_rk, 2)
        call grid%get_pairs(pairs, n)
        call brute_force_pairs(ends, rod, index, radius, 0.02_rk, 2, expected, n_expected)
        CHECK_TRUE(same_pairs(pairs, n, expected, n_expected), 'two clusters 1e8 apart')
        CHECK_TRUE(grid%n_cells() <= 8 * 300, 'two clusters: cells bounded by the segments')
        CHECK_TRUE(all(pairs(1, 1:n) > 150 .eqv. pairs(2, 1:n) > 150), 'no pair across clusters')
    end subroutine test_far_from_origin_and_sparse

    ! (2) A straight rod of 10 segments of length 0.1 and radius 0.12: boxes of segments i and j
    ! overlap for |i - j| <= 3 (gap (|i - j| - 1) 0.1 <= 2 radii = 0.24, no ties), so skip
    ! decides what is left.
    subroutine test_skip_rule_on_one_rod()
        integer, parameter :: m = 10
        real(rk) :: ends(3, 2, 2 * m), radius(2 * m)
        integer :: rod(2 * m), index(2 * m), i, n
        logical :: ok
        integer, allocatable :: pairs(:, :)
        type(contact_grid_t) :: grid
        do i = 1, m
            ends(:, 1, i) = [0.1_rk * (i - 1), 0.0_rk, 0.0_rk]
            ends(:, 2, i) = [0.1_rk * i, 0.0_rk, 0.0_rk]
            rod(i) = 7
            index(i) = i
        end do
        radius = 0.12_rk
        call grid%build(ends(:, :, 1:m), rod(1:m), index(1:m), radius(1:m), 0.0_rk, 2)
        call grid%get_pairs(pairs, n)
        CHECK_EQUAL(n, 7, 'skip 2: pairs at distance 3 along the rod only')
        ok = same_pairs(pairs, n, reshape([(i, i + 3, i = 1, 7)], [2, 7]), 7)
        CHECK_TRUE(ok, 'skip 2: (1,4), (2,5), ..., (7,10)')
        call grid%build(ends(:, :, 1:m), rod(1:m), index(1:m), radius(1:m), 0.0_rk, 3)
        CHECK_EQUAL(grid%n_pairs(), 0, 'skip 3: no candidate left')
        call grid%build(ends(:, :, 1:m), rod(1:m), index(1:m), radius(1:m), 0.0_rk, 0)
        CHECK_EQUAL(grid%n_pairs(), 9 + 8 + 7, 'skip 0: neighbours at distance 1, 2 and 3')
        ! A margin of 0.1 reaches one neighbour further (gap 0.3 <= 0.24 + 0.1 < 0.4).
        call grid%build(ends(:, :, 1:m), rod(1:m), index(1:m), radius(1:m), 0.1_rk, 3)
        call grid%get_pairs(pairs, n)
        ok = same_pairs(pairs, n, reshape([(i, i + 4, i = 1, 6)], [2, 6]), 6)
        CHECK_TRUE(ok, 'skip 3, margin 0.1: (1,5), ..., (6,10)')
        ! A second rod alongside (0.15 apart, boxes overlap sideways), same indices: skip
        ! applies within a rod only.
        do i = 1, m
            ends(:, :, m + i) = ends(:, :, i)
            ends(2, :, m + i) = 0.15_rk
            rod(m + i) = 8
            index(m + i) = i
        end do
        call grid%build(ends, rod, index, radius, 0.0_rk, 3)
        call grid%get_pairs(pairs, n)
        CHECK_EQUAL(n, 10 + 2 * (9 + 8 + 7), 'two rods: segment i meets i-3 .. i+3 of the other')
        CHECK_TRUE(all(rod(pairs(1, 1:n)) /= rod(pairs(2, 1:n))), 'skip 3: only pairs across rods')
        ok = all(abs(index(pairs(1, 1:n)) - index(pairs(2, 1:n))) <= 3)
        CHECK_TRUE(ok, 'across rods: index difference at most 3')
    end subroutine test_skip_rule_on_one_rod

    ! (3) Self contact of a helix (coil radius 1, pitch 0.15 < 2 rod radii = 0.2, 40 segments a
    ! turn, 3 turns): every segment has candidates one turn away; nothing within skip.
    subroutine test_helix_self_contact()
        integer, parameter :: per_turn = 40, m = 3 * per_turn, skip = 3
        real(rk), parameter :: pitch = 0.15_rk, r = 0.1_rk
        real(rk) :: ends(3, 2, m), radius(m), phi
        integer :: rod(m), index(m), s, k, n, n_expected, n_close, n_missing
        integer, allocatable :: pairs(:, :), expected(:, :)
        logical :: found
        type(contact_grid_t) :: grid
        do s = 1, m
            do k = 1, 2
                phi = 2.0_rk * pi * real(s - 2 + k, rk) / per_turn
                ends(:, k, s) = [cos(phi), sin(phi), pitch * phi / (2.0_rk * pi)]
            end do
        end do
        rod = 1
        index = [(s, s = 1, m)]
        radius = r
        call grid%build(ends, rod, index, radius, 0.0_rk, skip)
        call grid%get_pairs(pairs, n)
        call brute_force_pairs(ends, rod, index, radius, 0.0_rk, skip, expected, n_expected)
        CHECK_TRUE(same_pairs(pairs, n, expected, n_expected), 'helix: candidates = brute force')
        CHECK_TRUE(all(pairs(2, 1:n) - pairs(1, 1:n) > skip), 'helix: no neighbour within skip')
        do s = 1, m - per_turn
            found = .false.
            do k = 1, n
                if (all(pairs(:, k) == [s, s + per_turn])) found = .true.
            end do
            CHECK_TRUE(found, 'helix: segment and the one a turn later are candidates')
        end do
        call missing_contacts(ends, rod, index, radius, 0.0_rk, skip, pairs, n, n_close, n_missing)
        CHECK_TRUE(n_close >= m - per_turn, 'helix: turns within contact distance of each other')
        CHECK_EQUAL(n_missing, 0, 'helix: pairs within contact distance missed')
        ! A pitch of 3 rod radii takes the turns out of each other's boxes.
        ends(3, :, :) = ends(3, :, :) * (0.3_rk / pitch)
        call grid%build(ends, rod, index, radius, 0.0_rk, skip)
        CHECK_EQUAL(grid%n_pairs(), 0, 'helix with pitch 0.3 > 2 radii: no candidates')
    end subroutine test_helix_self_contact

    ! (4) The same input gives the same sorted list: rebuilt, on a grid that held a larger
    ! scene before, through candidate_pairs, and with other cell sizes.
    subroutine test_deterministic_and_sorted()
        type(contact_grid_t) :: grid, other
        real(rk), allocatable :: ends(:, :, :), radius(:), big_ends(:, :, :), big_radius(:)
        integer, allocatable :: rod(:), index(:), big_rod(:), big_index(:)
        integer, allocatable :: first(:, :), again(:, :)
        integer :: n_first, n, k
        real(rk), parameter :: cells(3) = [0.02_rk, 0.1_rk, 1.0_rk]
        call random_scene(500, 1.0_rk, 0.1_rk, 0.005_rk, 0.01_rk, 25, ends, rod, index, radius)
        call random_scene(2000, 2.0_rk, 0.2_rk, 0.005_rk, 0.02_rk, 25, big_ends, big_rod, &
            big_index, big_radius)
        call grid%build(ends, rod, index, radius, 0.01_rk, 1)
        call grid%get_pairs(first, n_first)
        CHECK_TRUE(n_first > 100, 'the scene has candidates')
        CHECK_TRUE(strictly_sorted(first, n_first), 'pairs a < b in strict lexicographic order')
        call grid%build(ends, rod, index, radius, 0.01_rk, 1)
        call grid%get_pairs(again, n)
        CHECK_TRUE(same_pairs(again, n, first, n_first), 'rebuilt: same list')
        call other%build(big_ends, big_rod, big_index, big_radius, 0.01_rk, 1)
        CHECK_TRUE(other%n_pairs() > n_first, 'the larger scene has more candidates')
        call other%build(ends, rod, index, radius, 0.01_rk, 1)
        call other%get_pairs(again, n)
        CHECK_TRUE(same_pairs(again, n, first, n_first), 'grid reused after a larger scene')
        do k = 1, n
            CHECK_TRUE(all(other%candidate(k) == first(:, k)), 'candidate(k) is column k')
        end do
        call candidate_pairs(ends, rod, index, radius, 0.01_rk, 1, again)
        CHECK_TRUE(same_pairs(again, size(again, 2), first, n_first), 'candidate_pairs: same list')
        do k = 1, size(cells)
            call grid%build(ends, rod, index, radius, 0.01_rk, 1, cell_size=cells(k))
            call grid%get_pairs(again, n)
            CHECK_TRUE(same_pairs(again, n, first, n_first), 'other cell size: same list')
        end do
    end subroutine test_deterministic_and_sorted

    ! (5) 10^4 and 4 x 10^4 segments at the same density (8 a unit volume, length <= 1, radius
    ! 0.05, margin 0.05): times reported, not asserted; the candidates of the first 200
    ! segments checked against brute force over all segments.
    subroutine test_large_scenes_scale()
        integer, parameter :: sizes(2) = [10000, 40000], n_checked = 200
        real(rk), parameter :: margin = 0.05_rk
        type(contact_grid_t) :: grid
        real(rk), allocatable :: ends(:, :, :), radius(:)
        integer, allocatable :: rod(:), index(:), pairs(:, :), partners(:)
        real(rk) :: t0, t_first, t_again, lo(3, 2), hi(3, 2)
        integer :: i, n, a, b, k, n_partners, n_mismatch, n_extra
        allocate(partners(maxval(sizes)))
        do i = 1, size(sizes)
            call random_scene(sizes(i), real(sizes(i) / 8, rk)**(1.0_rk / 3.0_rk), 1.0_rk, 0.05_rk, &
                0.05_rk, 50, ends, rod, index, radius)
            call grid%free()
            t0 = wall_time()
            call grid%build(ends, rod, index, radius, margin, 1)
            t_first = wall_time() - t0
            t0 = wall_time()
            call grid%build(ends, rod, index, radius, margin, 1)
            t_again = wall_time() - t0
            call grid%get_pairs(pairs, n)
            write(output_unit, '(a,i6,a,f8.4,a,f8.4,a,i7,a,i7,a,i7)') '    M = ', sizes(i), &
                ': build ', t_first, ' s (first), ', t_again, ' s (workspace reused); pairs ', &
                n, ', cells ', grid%n_cells(), ', registrations ', grid%n_registrations()
            CHECK_TRUE(strictly_sorted(pairs, n), 'large scene: sorted')
            CHECK_TRUE(grid%n_registrations() <= 8 * sizes(i), 'large scene: <= 8 cells a box')
            CHECK_TRUE(n > sizes(i), 'large scene: more candidates than segments')
            ! Brute force for the first segments: their partners b > a in increasing order must
            ! be the next block of the sorted list.
            n_mismatch = 0
            k = 1
            do a = 1, n_checked
                lo(:, 1) = min(ends(:, 1, a), ends(:, 2, a)) - (radius(a) + 0.5_rk * margin)
                hi(:, 1) = max(ends(:, 1, a), ends(:, 2, a)) + (radius(a) + 0.5_rk * margin)
                n_partners = 0
                do b = a + 1, sizes(i)
                    if (rod(a) == rod(b) .and. abs(index(a) - index(b)) <= 1) cycle
                    lo(:, 2) = min(ends(:, 1, b), ends(:, 2, b)) - (radius(b) + 0.5_rk * margin)
                    hi(:, 2) = max(ends(:, 1, b), ends(:, 2, b)) + (radius(b) + 0.5_rk * margin)
                    if (any(lo(:, 1) > hi(:, 2)) .or. any(lo(:, 2) > hi(:, 1))) cycle
                    n_partners = n_partners + 1
                    partners(n_partners) = b
                end do
                do b = 1, n_partners
                    if (k > n) then
                        n_mismatch = n_mismatch + 1
                    else if (any(pairs(:, k) /= [a, partners(b)])) then
                        n_mismatch = n_mismatch + 1
                    end if
                    k = k + 1
                end do
            end do
            CHECK_EQUAL(n_mismatch, 0, 'large scene: first segments against brute force')
            n_extra = count(pairs(1, 1:n) <= n_checked) - (k - 1)
            CHECK_EQUAL(n_extra, 0, 'large scene: no extra candidate of the first segments')
        end do
    end subroutine test_large_scenes_scale

    ! (6) No segment, one segment, all segments in one cell, coincident segments and points.
    subroutine test_degenerate_inputs()
        type(contact_grid_t) :: grid
        real(rk) :: none(3, 2, 0), no_radius(0), same(3, 2, 6), points(3, 2, 4)
        real(rk), parameter :: six_radii(6) = 0.1_rk, no_radii(4) = 0.0_rk
        integer :: no_int(0), n, n_expected, s
        logical :: ok
        integer, allocatable :: pairs(:, :), expected(:, :)
        real(rk), allocatable :: ends(:, :, :), radius(:)
        integer, allocatable :: rod(:), index(:)
        call grid%build(none, no_int, no_int, no_radius, 0.1_rk, 1)
        call grid%get_pairs(pairs, n)
        CHECK_EQUAL(n, 0, 'no segment: no pair')
        call candidate_pairs(none, no_int, no_int, no_radius, 0.1_rk, 1, pairs)
        CHECK_EQUAL(size(pairs, 2), 0, 'no segment: candidate_pairs gives (2, 0)')
        call grid%build(reshape([0.0_rk, 0.0_rk, 0.0_rk, 1.0_rk, 0.0_rk, 0.0_rk], [3, 2, 1]), &
            [1], [1], [0.1_rk], 0.1_rk, 1)
        CHECK_EQUAL(grid%n_pairs(), 0, 'one segment: no pair')
        CHECK_TRUE(grid%n_cells() >= 1, 'one segment: registered')
        ! All segments in one cell.
        call random_scene(40, 0.1_rk, 0.05_rk, 0.01_rk, 0.02_rk, 10, ends, rod, index, radius)
        call grid%build(ends, rod, index, radius, 0.0_rk, 1, cell_size=100.0_rk)
        call grid%get_pairs(pairs, n)
        call brute_force_pairs(ends, rod, index, radius, 0.0_rk, 1, expected, n_expected)
        CHECK_EQUAL(grid%n_cells(), 1, 'cell side 100: one cell')
        CHECK_TRUE(n_expected > 100, 'the crowded scene has many box-overlap pairs')
        CHECK_TRUE(same_pairs(pairs, n, expected, n_expected), 'one cell: = brute force')
        ! Six coincident segments.
        do s = 1, 6
            same(:, 1, s) = [0.5_rk, -0.25_rk, 2.0_rk]
            same(:, 2, s) = [0.75_rk, 0.5_rk, 2.0_rk]
        end do
        call grid%build(same, [1, 2, 3, 4, 5, 6], [1, 1, 1, 1, 1, 1], six_radii, 0.0_rk, 2)
        CHECK_EQUAL(grid%n_pairs(), 15, 'six coincident segments of six rods: every pair')
        call grid%build(same, [1, 1, 1, 1, 1, 1], [1, 2, 3, 4, 5, 6], six_radii, 0.0_rk, 2)
        call grid%get_pairs(pairs, n)
        ok = same_pairs(pairs, n, reshape([1, 4, 1, 5, 1, 6, 2, 5, 2, 6, 3, 6], [2, 6]), 6)
        CHECK_TRUE(ok, 'six coincident segments of one rod, skip 2: index differences >= 3')
        call grid%build(same, [1, 1, 1, 1, 1, 1], [1, 1, 1, 1, 1, 1], six_radii, 0.0_rk, 0)
        CHECK_EQUAL(grid%n_pairs(), 0, 'coincident segments with one index on one rod: skipped')
        ! Points (zero length, radius and margin): coincident ones touch, a distinct one does not.
        points = 0.0_rk
        points(:, :, 4) = 1.0_rk
        call grid%build(points, [1, 2, 3, 4], [1, 1, 1, 1], no_radii, 0.0_rk, 0)
        call grid%get_pairs(pairs, n)
        ok = same_pairs(pairs, n, reshape([1, 2, 1, 3, 2, 3], [2, 3]), 3)
        CHECK_TRUE(ok, 'points: the three coincident ones pair up')
        CHECK_TRUE(grid%cell_size() > 0.0_rk, 'points: a positive cell side')
        call grid%build(points(:, :, 1:3), [1, 2, 3], [1, 1, 1], no_radii(1:3), 0.0_rk, 0)
        CHECK_EQUAL(grid%n_pairs(), 3, 'three coincident points only: three pairs')
        CHECK_EQUAL(grid%n_cells(), 1, 'three coincident points only: one cell')
    end subroutine test_degenerate_inputs

end module rs_test_contact_grid

program test_contact_grid
    use rs_test_contact_grid, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_contact_grid
