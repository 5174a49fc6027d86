!> The nonzero pattern of a sparse Jacobian in compressed-row form, built once per run from the
!> couplings the formulation declares (DESIGN.md §3: exact preallocation, so the symbolic
!> factorization is done once). Pure Fortran: the solver hands the arrays to PETSc.
!>
!> Rows and columns are 1-based here; `row_ptr` and `cols` are returned 0-based for PETSc by
!> `zero_based`. A coupling is declared as a dense block `rows x cols`, optionally masked; the
!> builder keeps the pairs, sorts each row and removes duplicates.
module rs_assembly_csr_pattern
    implicit none
    private

    !> Collects (row, col) couplings; `build` turns them into a pattern.
    type, public :: csr_builder_t
        integer :: n_rows = 0
        integer :: n_pairs = 0
        integer, allocatable :: pair_row(:), pair_col(:)
    contains
        procedure :: init => builder_init
        procedure :: add_block => builder_add_block
        procedure :: build => builder_build
    end type csr_builder_t

    !> A compressed-row pattern: row i has columns cols(row_ptr(i) : row_ptr(i+1)-1), sorted.
    type, public :: csr_pattern_t
        integer :: n_rows = 0
        integer, allocatable :: row_ptr(:)
        integer, allocatable :: cols(:)
    contains
        procedure :: nnz => pattern_nnz
        procedure :: position => pattern_position
        procedure :: zero_based => pattern_zero_based
    end type csr_pattern_t

contains

    !> Start a builder for `n_rows` rows, with room for about `expected_pairs` couplings.
    subroutine builder_init(this, n_rows, expected_pairs)
        class(csr_builder_t), intent(inout) :: this
        integer, intent(in) :: n_rows, expected_pairs
        this%n_rows = n_rows
        this%n_pairs = 0
        if (allocated(this%pair_row)) deallocate(this%pair_row, this%pair_col)
        allocate(this%pair_row(max(16, expected_pairs)), this%pair_col(max(16, expected_pairs)))
    end subroutine builder_init

    !> Declare that every row in `rows` couples to every column in `cols` where `mask` (if
    !> given, shape [size(rows), size(cols)]) is true. Entries <= 0 are skipped (fixed dofs).
    subroutine builder_add_block(this, rows, cols, mask)
        class(csr_builder_t), intent(inout) :: this
        integer, intent(in) :: rows(:), cols(:)
        logical, intent(in), optional :: mask(:, :)
        integer :: i, j
        call reserve(this, size(rows) * size(cols))
        do j = 1, size(cols)
            if (cols(j) <= 0) cycle
            do i = 1, size(rows)
                if (rows(i) <= 0) cycle
                if (present(mask)) then
                    if (.not. mask(i, j)) cycle
                end if
                this%n_pairs = this%n_pairs + 1
                this%pair_row(this%n_pairs) = rows(i)
                this%pair_col(this%n_pairs) = cols(j)
            end do
        end do
    end subroutine builder_add_block

    subroutine reserve(this, extra)
        type(csr_builder_t), intent(inout) :: this
        integer, intent(in) :: extra
        integer, allocatable :: grown(:)
        integer :: capacity
        capacity = size(this%pair_row)
        if (this%n_pairs + extra <= capacity) return
        capacity = max(2 * capacity, this%n_pairs + extra)
        allocate(grown(capacity))
        grown(1:this%n_pairs) = this%pair_row(1:this%n_pairs)
        call move_alloc(grown, this%pair_row)
        allocate(grown(capacity))
        grown(1:this%n_pairs) = this%pair_col(1:this%n_pairs)
        call move_alloc(grown, this%pair_col)
    end subroutine reserve

    !> The pattern of all declared couplings (each row sorted, duplicates removed). Frees the
    !> builder's pair lists.
    subroutine builder_build(this, pattern)
        class(csr_builder_t), intent(inout) :: this
        type(csr_pattern_t), intent(out) :: pattern
        integer, allocatable :: start(:), bucket(:), fill(:), seen_in_row(:)
        integer :: i, k, r, c, first, last, n_unique, n_cols
        ! Counting sort of the pairs by row; in each row the duplicates are dropped with a
        ! marker per column (a contact pair declares its block once per pair: rows of a bundle
        ! hold each column many times) and the distinct columns sorted.
        allocate(start(this%n_rows + 1), source=0)
        do k = 1, this%n_pairs
            start(this%pair_row(k) + 1) = start(this%pair_row(k) + 1) + 1
        end do
        start(1) = 1
        do r = 1, this%n_rows
            start(r + 1) = start(r + 1) + start(r)
        end do
        allocate(bucket(this%n_pairs), fill(this%n_rows))
        fill = start(1:this%n_rows)
        do k = 1, this%n_pairs
            r = this%pair_row(k)
            bucket(fill(r)) = this%pair_col(k)
            fill(r) = fill(r) + 1
        end do
        n_cols = 0
        if (this%n_pairs > 0) n_cols = maxval(this%pair_col(1:this%n_pairs))
        allocate(seen_in_row(n_cols), source=0)
        deallocate(this%pair_row, this%pair_col)
        this%n_pairs = 0

        pattern%n_rows = this%n_rows
        allocate(pattern%row_ptr(this%n_rows + 1))
        n_unique = 0
        pattern%row_ptr(1) = 1
        do r = 1, this%n_rows
            first = start(r)
            last = start(r + 1) - 1
            k = 0
            do i = first, last
                c = bucket(i)
                if (seen_in_row(c) == r) cycle
                seen_in_row(c) = r
                bucket(first + k) = c
                k = k + 1
            end do
            call sort_ascending(bucket(first:first + k - 1))
            do i = 0, k - 1
                n_unique = n_unique + 1
                bucket(n_unique) = bucket(first + i)
            end do
            pattern%row_ptr(r + 1) = n_unique + 1
        end do
        pattern%cols = bucket(1:n_unique)
    end subroutine builder_build

    !> Sort distinct `values` ascending: insertion for a short row, heap sort (n log n) for a
    !> long one (a bundle's contact rows hold hundreds of columns).
    pure subroutine sort_ascending(values)
        integer, intent(inout) :: values(:)
        integer :: i, j, key, n
        n = size(values)
        if (n <= 32) then
            do i = 2, n
                key = values(i)
                j = i - 1
                do while (j >= 1)
                    if (values(j) <= key) exit
                    values(j + 1) = values(j)
                    j = j - 1
                end do
                values(j + 1) = key
            end do
            return
        end if
        do i = n / 2, 1, -1
            call sift_down(values, i, n)
        end do
        do i = n, 2, -1
            key = values(1)
            values(1) = values(i)
            values(i) = key
            call sift_down(values, 1, i - 1)
        end do
    end subroutine sort_ascending

    !> Restore the max-heap below `root` in values(1:last).
    pure subroutine sift_down(values, root, last)
        integer, intent(inout) :: values(:)
        integer, intent(in) :: root, last
        integer :: parent, child, key
        parent = root
        key = values(parent)
        do
            child = 2 * parent
            if (child > last) exit
            if (child < last) then
                if (values(child + 1) > values(child)) child = child + 1
            end if
            if (values(child) <= key) exit
            values(parent) = values(child)
            parent = child
        end do
        values(parent) = key
    end subroutine sift_down

    !> Number of stored entries.
    pure integer function pattern_nnz(this)
        class(csr_pattern_t), intent(in) :: this
        pattern_nnz = this%row_ptr(this%n_rows + 1) - 1
    end function pattern_nnz

    !> 1-based index of entry (row, col) in the value array, or 0 if it is not in the pattern
    !> (row or column outside the matrix included).
    pure integer function pattern_position(this, row, col) result(position)
        class(csr_pattern_t), intent(in) :: this
        integer, intent(in) :: row, col
        integer :: low, high, middle
        position = 0
        if (row <= 0 .or. col <= 0 .or. row > this%n_rows) return
        low = this%row_ptr(row)
        high = this%row_ptr(row + 1) - 1
        do while (low <= high)
            middle = (low + high) / 2
            if (this%cols(middle) == col) then
                position = middle
                return
            else if (this%cols(middle) < col) then
                low = middle + 1
            else
                high = middle - 1
            end if
        end do
    end function pattern_position

    !> The pattern as 0-based arrays, as PETSc's MatSeqAIJSetPreallocationCSR wants them.
    subroutine pattern_zero_based(this, row_ptr, cols)
        class(csr_pattern_t), intent(in) :: this
        integer, allocatable, intent(out) :: row_ptr(:), cols(:)
        row_ptr = this%row_ptr - 1
        cols = this%cols - 1
    end subroutine pattern_zero_based

end module rs_assembly_csr_pattern
