!> Broad phase of rod-rod and self contact: the candidate segment pairs of a scene, found with a
!> uniform cell grid (DESIGN.md §5: "Candidate pairs come from a cell grid with a margin; a step
!> is redone if a new pair enters").
!>
!> Candidates. Segment s has end points ends(:, 1, s) and ends(:, 2, s), a rod id, an index along
!> its rod and a radius. Its box is the axis-aligned bounding box of its two end points inflated
!> on every side by radius(s) + margin / 2. Segments a < b are a candidate pair when their boxes
!> overlap (closed boxes: touching counts) and they are not near neighbours on one rod, i.e. not
!> (rod(a) == rod(b) and |index(a) - index(b)| <= skip). Self contact of a rod beyond `skip`
!> neighbours is a candidate like any other pair. Since a box holds every point within
!> radius + margin / 2 of its centreline segment, every pair whose centrelines come within
!> radius(a) + radius(b) + margin of each other is a candidate.
!>
!> Method. A uniform grid of cubic cells of side h over the scene's bounding box (default h: the
!> largest side of any box, so that a box touches at most 2 x 2 x 2 cells). Each segment is
!> registered in every cell its box touches; occupied cells are numbered through an
!> open-addressing hash of their integer coordinates, so memory is O(M) however sparse the scene
!> and cell coordinates are taken relative to the scene's lower corner (no dependence on the size
!> of absolute coordinates). The segments of each cell are tested pairwise, and a pair is kept
!> only in the cell that contains the lower corner of the intersection of its two boxes, which
!> reports it exactly once. Two stable counting sorts (by b, then by a) put the pairs in
!> lexicographic order. Cost O(M + P) for bounded density, P the number of candidates; the result
!> depends only on the input, so it is the same on every rank and every run.
!>
!> Workspace. `contact_grid_t` keeps all arrays between calls and grows them by doubling only, so
!> the time loop can rebuild it every step without allocating once the largest scene was seen.
module rs_contact_grid
    use rs_core_kinds, only: rk, i8
    implicit none
    private

    public :: candidate_pairs, reserve_int_2

    !> Persistent broad-phase workspace and its last result: `build`, then `get_pairs` (or
    !> `n_pairs` and `candidate`).
    type, public :: contact_grid_t
        private
        integer :: n_entries = 0
        integer :: n_occupied = 0
        integer :: n_found = 0
        real(rk) :: h = 0.0_rk
        real(rk) :: origin(3) = 0.0_rk
        ! Inflated boxes (3, M) and the cell ranges they touch (3, M).
        real(rk), allocatable :: lo(:, :), hi(:, :)
        integer(i8), allocatable :: cell_lo(:, :), cell_hi(:, :)
        ! Hash table of occupied cells (cell number or 0) and their coordinates (3, cells).
        integer, allocatable :: slot(:)
        integer(i8), allocatable :: cell_xyz(:, :)
        ! Cell of every (segment, cell) entry, in segment order; cells' segments in CSR form.
        integer, allocatable :: entry_cell(:)
        integer, allocatable :: first(:), member(:)
        ! Candidate pairs (2, P), sorting scratch and counts.
        integer, allocatable :: pair(:, :), pair_scratch(:, :), counts(:)
    contains
        !> Empty the grid, keeping nothing.
        procedure :: init => grid_init
        !> Release all workspace.
        procedure :: free => grid_free
        !> Find the candidate pairs of a set of segments.
        procedure :: build => grid_build
        !> Copy the candidate pairs of the last build.
        procedure :: get_pairs => grid_get_pairs
        !> Number of candidate pairs of the last build.
        procedure :: n_pairs => grid_n_pairs
        !> Candidate pair k (1 <= k <= n_pairs) of the last build, [a, b] with a < b.
        procedure :: candidate => grid_candidate
        !> Cell side used by the last build.
        procedure :: cell_size => grid_cell_size
        !> Number of occupied cells in the last build.
        procedure :: n_cells => grid_n_cells
        !> Number of (segment, cell) registrations in the last build.
        procedure :: n_registrations => grid_n_registrations
    end type contact_grid_t

    !> A given cell side is raised to at least this fraction of the largest box side, so a box
    !> touches at most 18 cells along each axis.
    real(rk), parameter :: min_cell_fraction = 1.0_rk / 16.0_rk
    !> ... and to at least this fraction of the scene's extent, so cell coordinates stay < 2**41.
    real(rk), parameter :: min_cell_of_scene = 2.0_rk**(-40)

contains

    pure subroutine grid_init(this)
        class(contact_grid_t), intent(inout) :: this
        call this%free()
    end subroutine grid_init

    pure subroutine grid_free(this)
        class(contact_grid_t), intent(inout) :: this
        if (allocated(this%lo)) deallocate(this%lo)
        if (allocated(this%hi)) deallocate(this%hi)
        if (allocated(this%cell_lo)) deallocate(this%cell_lo)
        if (allocated(this%cell_hi)) deallocate(this%cell_hi)
        if (allocated(this%slot)) deallocate(this%slot)
        if (allocated(this%cell_xyz)) deallocate(this%cell_xyz)
        if (allocated(this%entry_cell)) deallocate(this%entry_cell)
        if (allocated(this%first)) deallocate(this%first)
        if (allocated(this%member)) deallocate(this%member)
        if (allocated(this%pair)) deallocate(this%pair)
        if (allocated(this%pair_scratch)) deallocate(this%pair_scratch)
        if (allocated(this%counts)) deallocate(this%counts)
        this%n_entries = 0
        this%n_occupied = 0
        this%n_found = 0
        this%h = 0.0_rk
        this%origin = 0.0_rk
    end subroutine grid_free

    !> Find the candidate pairs of segments 1..M (M = size(ends, 3)); see the module header for
    !> the rule. `rod`, `index` and `radius` have M entries; `margin` >= 0 and `skip` >= 0 (a
    !> negative skip leaves out nothing). `cell_size` > 0 overrides the default cell side (the
    !> largest box side); it is raised to 1/16 of that side if smaller. Inputs must be finite.
    pure subroutine grid_build(this, ends, rod, index, radius, margin, skip, cell_size)
        class(contact_grid_t), intent(inout) :: this
        real(rk), intent(in) :: ends(:, :, :)
        integer, intent(in) :: rod(:), index(:)
        real(rk), intent(in) :: radius(:)
        real(rk), intent(in) :: margin
        integer, intent(in) :: skip
        real(rk), intent(in), optional :: cell_size
        real(rk) :: largest_side, extent, top(3)
        integer :: m, s, d
        integer(i8) :: n_entries
        m = size(ends, 3)
        this%n_entries = 0
        this%n_occupied = 0
        this%n_found = 0
        this%h = 0.0_rk
        this%origin = 0.0_rk
        if (m == 0) return
        call reserve_real_2(this%lo, 3, m)
        call reserve_real_2(this%hi, 3, m)
        call reserve_i8_2(this%cell_lo, 3, m)
        call reserve_i8_2(this%cell_hi, 3, m)
        ! Cell coordinates count from the scene's lower corner (loops: no array temporaries).
        this%origin = huge(1.0_rk)
        top = -huge(1.0_rk)
        largest_side = 0.0_rk
        do s = 1, m
            this%lo(:, s) = min(ends(:, 1, s), ends(:, 2, s)) - (radius(s) + 0.5_rk * margin)
            this%hi(:, s) = max(ends(:, 1, s), ends(:, 2, s)) + (radius(s) + 0.5_rk * margin)
            this%origin = min(this%origin, this%lo(:, s))
            top = max(top, this%hi(:, s))
            largest_side = max(largest_side, maxval(this%hi(:, s) - this%lo(:, s)))
        end do
        extent = max(0.0_rk, maxval(top - this%origin))
        this%h = largest_side
        if (present(cell_size)) then
            if (cell_size > 0.0_rk) this%h = max(cell_size, min_cell_fraction * largest_side)
        end if
        this%h = max(this%h, min_cell_of_scene * extent)
        ! Boxes of zero size in a scene of zero size: any positive side will do.
        if (.not. this%h > 0.0_rk) this%h = 1.0_rk
        n_entries = 0
        do s = 1, m
            do d = 1, 3
                this%cell_lo(d, s) = cell_coordinate(this%lo(d, s), this%origin(d), this%h)
                this%cell_hi(d, s) = cell_coordinate(this%hi(d, s), this%origin(d), this%h)
            end do
            n_entries = n_entries + cells_touched(this%cell_lo(:, s), this%cell_hi(:, s))
        end do
        this%n_entries = int(n_entries)
        call register_segments(this, m)
        call collect_pairs(this, rod, index, skip)
        call sort_pairs(this, m)
    end subroutine grid_build

    !> Number the occupied cells through the hash table and list each cell's segments (CSR,
    !> segments in increasing order within a cell).
    pure subroutine register_segments(this, m)
        type(contact_grid_t), intent(inout) :: this
        integer, intent(in) :: m
        integer(i8) :: c(3), mask
        integer :: capacity, s, e, i, j, k, id, n_cells
        capacity = 16
        do while (capacity < 2 * this%n_entries)
            capacity = 2 * capacity
        end do
        mask = int(capacity - 1, i8)
        call reserve_int_1(this%slot, capacity)
        this%slot(1:capacity) = 0
        call reserve_i8_2(this%cell_xyz, 3, max(this%n_entries, 1))
        call reserve_int_1(this%entry_cell, max(this%n_entries, 1))
        call reserve_int_1(this%first, this%n_entries + 1)
        call reserve_int_1(this%member, max(this%n_entries, 1))
        n_cells = 0
        e = 0
        do s = 1, m
            do k = 0, int(this%cell_hi(3, s) - this%cell_lo(3, s))
                do j = 0, int(this%cell_hi(2, s) - this%cell_lo(2, s))
                    do i = 0, int(this%cell_hi(1, s) - this%cell_lo(1, s))
                        c = this%cell_lo(:, s) + [int(i, i8), int(j, i8), int(k, i8)]
                        call find_or_insert(this, c, mask, n_cells, id)
                        e = e + 1
                        this%entry_cell(e) = id
                    end do
                end do
            end do
        end do
        this%n_occupied = n_cells
        ! Counting sort of the entries by cell; entries are in segment order, so each cell's
        ! segments come out increasing.
        this%first(1:n_cells + 1) = 0
        do e = 1, this%n_entries
            id = this%entry_cell(e)
            this%first(id + 1) = this%first(id + 1) + 1
        end do
        this%first(1) = 1
        do id = 1, n_cells
            this%first(id + 1) = this%first(id + 1) + this%first(id)
        end do
        e = 0
        do s = 1, m
            do k = 1, int(cells_touched(this%cell_lo(:, s), this%cell_hi(:, s)))
                e = e + 1
                id = this%entry_cell(e)
                this%member(this%first(id)) = s
                this%first(id) = this%first(id) + 1
            end do
        end do
        ! first(id) now points past cell id's segments: shift back.
        do id = n_cells, 1, -1
            this%first(id + 1) = this%first(id)
        end do
        this%first(1) = 1
    end subroutine register_segments

    !> The number of cell `c` (linear probing), inserting it if it is new.
    pure subroutine find_or_insert(this, c, mask, n_cells, id)
        type(contact_grid_t), intent(inout) :: this
        integer(i8), intent(in) :: c(3), mask
        integer, intent(inout) :: n_cells
        integer, intent(out) :: id
        integer :: p
        p = int(iand(cell_hash(c), mask)) + 1
        do
            id = this%slot(p)
            if (id == 0) then
                n_cells = n_cells + 1
                id = n_cells
                this%slot(p) = id
                this%cell_xyz(:, id) = c
                return
            end if
            if (all(this%cell_xyz(:, id) == c)) return
            p = p + 1
            if (p > size(this%slot)) p = 1
        end do
    end subroutine find_or_insert

    !> Test the segment pairs of every cell; keep a pair in the cell holding the lower corner of
    !> its boxes' intersection only.
    pure subroutine collect_pairs(this, rod, index, skip)
        type(contact_grid_t), intent(inout) :: this
        integer, intent(in) :: rod(:), index(:), skip
        integer :: id, i, j, a, b, d
        logical :: owned
        if (.not. allocated(this%pair)) allocate(this%pair(2, 64))
        do id = 1, this%n_occupied
            do i = this%first(id), this%first(id + 1) - 1
                a = this%member(i)
                do j = i + 1, this%first(id + 1) - 1
                    b = this%member(j)
                    if (rod(a) == rod(b) .and. abs(index(a) - index(b)) <= skip) cycle
                    if (any(this%lo(:, a) > this%hi(:, b))) cycle
                    if (any(this%lo(:, b) > this%hi(:, a))) cycle
                    owned = .true.
                    do d = 1, 3
                        owned = owned .and. cell_coordinate(max(this%lo(d, a), this%lo(d, b)), &
                            this%origin(d), this%h) == this%cell_xyz(d, id)
                    end do
                    if (.not. owned) cycle
                    if (this%n_found == size(this%pair, 2)) then
                        call grow_pairs(this%pair, this%n_found)
                    end if
                    this%n_found = this%n_found + 1
                    this%pair(:, this%n_found) = [a, b]
                end do
            end do
        end do
    end subroutine collect_pairs

    !> Lexicographic order of the pairs: a stable counting sort by b, then one by a (both keys
    !> lie in 1..M).
    pure subroutine sort_pairs(this, m)
        type(contact_grid_t), intent(inout) :: this
        integer, intent(in) :: m
        integer :: n
        n = this%n_found
        if (n < 2) return
        call reserve_int_2(this%pair_scratch, 2, n)
        call reserve_int_1(this%counts, m + 1)
        call counting_sort(this%pair, this%pair_scratch, 2, n, m, this%counts)
        call counting_sort(this%pair_scratch, this%pair, 1, n, m, this%counts)
    end subroutine sort_pairs

    !> Stable counting sort of columns 1..n of `from` into `to` by row `key` (values 1..m).
    pure subroutine counting_sort(from, to, key, n, m, counts)
        integer, intent(in) :: from(:, :)
        integer, intent(inout) :: to(:, :), counts(:)
        integer, intent(in) :: key, n, m
        integer :: k, v
        counts(1:m + 1) = 0
        do k = 1, n
            v = from(key, k)
            counts(v + 1) = counts(v + 1) + 1
        end do
        counts(1) = 1
        do v = 1, m
            counts(v + 1) = counts(v + 1) + counts(v)
        end do
        do k = 1, n
            v = from(key, k)
            to(:, counts(v)) = from(:, k)
            counts(v) = counts(v) + 1
        end do
    end subroutine counting_sort

    !> Copy the candidate pairs of the last build into columns 1..n of `pairs_out` (2, :), which
    !> is allocated or grown (by doubling) only when too small.
    pure subroutine grid_get_pairs(this, pairs_out, n)
        class(contact_grid_t), intent(in) :: this
        integer, allocatable, intent(inout) :: pairs_out(:, :)
        integer, intent(out) :: n
        integer :: capacity
        n = this%n_found
        ! -1: not there yet, or of the wrong shape.
        capacity = -1
        if (allocated(pairs_out)) then
            if (size(pairs_out, 1) == 2) capacity = size(pairs_out, 2)
        end if
        if (capacity < n) then
            if (allocated(pairs_out)) deallocate(pairs_out)
            allocate(pairs_out(2, max(n, 2 * capacity)))
        end if
        if (n > 0) pairs_out(:, 1:n) = this%pair(:, 1:n)
    end subroutine grid_get_pairs

    pure integer function grid_n_pairs(this)
        class(contact_grid_t), intent(in) :: this
        grid_n_pairs = this%n_found
    end function grid_n_pairs

    pure function grid_candidate(this, k) result(ab)
        class(contact_grid_t), intent(in) :: this
        integer, intent(in) :: k
        integer :: ab(2)
        ab = this%pair(:, k)
    end function grid_candidate

    pure real(rk) function grid_cell_size(this)
        class(contact_grid_t), intent(in) :: this
        grid_cell_size = this%h
    end function grid_cell_size

    pure integer function grid_n_cells(this)
        class(contact_grid_t), intent(in) :: this
        grid_n_cells = this%n_occupied
    end function grid_n_cells

    pure integer function grid_n_registrations(this)
        class(contact_grid_t), intent(in) :: this
        grid_n_registrations = this%n_entries
    end function grid_n_registrations

    !> The candidate pairs (2, n) of one set of segments, in lexicographic order: a one-off
    !> `contact_grid_t` build (it allocates its workspace on every call; a time loop keeps a
    !> `contact_grid_t` instead).
    pure subroutine candidate_pairs(ends, rod, index, radius, margin, skip, pairs, cell_size)
        real(rk), intent(in) :: ends(:, :, :)
        integer, intent(in) :: rod(:), index(:)
        real(rk), intent(in) :: radius(:)
        real(rk), intent(in) :: margin
        integer, intent(in) :: skip
        integer, allocatable, intent(out) :: pairs(:, :)
        real(rk), intent(in), optional :: cell_size
        type(contact_grid_t) :: grid
        integer :: n
        call grid%build(ends, rod, index, radius, margin, skip, cell_size)
        n = grid%n_pairs()
        allocate(pairs(2, n))
        if (n > 0) pairs = grid%pair(:, 1:n)
    end subroutine candidate_pairs

    !> Cell coordinate of x along one axis. Monotone in x, so the cells of a box's corners bound
    !> the cells of every point inside it.
    pure integer(i8) function cell_coordinate(x, origin, h)
        real(rk), intent(in) :: x, origin, h
        cell_coordinate = int((x - origin) / h, i8)
    end function cell_coordinate

    !> Number of cells in the range lo..hi (0 for an empty range: a box shrunk by a negative
    !> inflation).
    pure integer(i8) function cells_touched(lo, hi)
        integer(i8), intent(in) :: lo(3), hi(3)
        cells_touched = product(max(hi - lo + 1, 0_i8))
    end function cells_touched

    !> Hash of non-negative cell coordinates (< 2**41): each wrapped to 21 bits and weighted by a
    !> large odd prime, which stays below 2**50 (no overflow).
    pure integer(i8) function cell_hash(c)
        integer(i8), intent(in) :: c(3)
        integer(i8), parameter :: wrap = 2_i8**21
        cell_hash = modulo(c(1), wrap) * 73856093_i8 + modulo(c(2), wrap) * 19349663_i8 &
            + modulo(c(3), wrap) * 83492791_i8
    end function cell_hash

    !> Double the pair list, keeping its first n columns.
    pure subroutine grow_pairs(pair, n)
        integer, allocatable, intent(inout) :: pair(:, :)
        integer, intent(in) :: n
        integer, allocatable :: grown(:, :)
        allocate(grown(2, 2 * size(pair, 2)))
        grown(:, 1:n) = pair(:, 1:n)
        call move_alloc(grown, pair)
    end subroutine grow_pairs

    !> Make `a` hold at least n entries (contents are not kept).
    pure subroutine reserve_int_1(a, n)
        integer, allocatable, intent(inout) :: a(:)
        integer, intent(in) :: n
        integer :: capacity
        capacity = 0
        if (allocated(a)) capacity = size(a)
        if (capacity >= n) return
        if (allocated(a)) deallocate(a)
        allocate(a(max(n, 2 * capacity)))
    end subroutine reserve_int_1

    !> Make `a` hold at least rows x n entries (contents are not kept).
    pure subroutine reserve_int_2(a, rows, n)
        integer, allocatable, intent(inout) :: a(:, :)
        integer, intent(in) :: rows, n
        integer :: capacity
        capacity = 0
        if (allocated(a)) capacity = size(a, 2)
        if (capacity >= n) return
        if (allocated(a)) deallocate(a)
        allocate(a(rows, max(n, 2 * capacity)))
    end subroutine reserve_int_2

    pure subroutine reserve_i8_2(a, rows, n)
        integer(i8), allocatable, intent(inout) :: a(:, :)
        integer, intent(in) :: rows, n
        integer :: capacity
        capacity = 0
        if (allocated(a)) capacity = size(a, 2)
        if (capacity >= n) return
        if (allocated(a)) deallocate(a)
        allocate(a(rows, max(n, 2 * capacity)))
    end subroutine reserve_i8_2

    pure subroutine reserve_real_2(a, rows, n)
        real(rk), allocatable, intent(inout) :: a(:, :)
        integer, intent(in) :: rows, n
        integer :: capacity
        capacity = 0
        if (allocated(a)) capacity = size(a, 2)
        if (capacity >= n) return
        if (allocated(a)) deallocate(a)
        allocate(a(rows, max(n, 2 * capacity)))
    end subroutine reserve_real_2

end module rs_contact_grid
