#include "rs_assert.h"
!> Unit tests of rs_assembly_csr_pattern: a hand-worked pattern with duplicate, masked and
!> skipped (<= 0) entries (sorted unique rows, nnz, row pointers, `position` of every entry and 0
!> for absent ones, out-of-range rows and row/col <= 0, 0-based output), empty rows and an
!> empty builder, and seeded random sets of blocks compared against a dense logical matrix that
!> the test builds on its own.
module rs_test_assembly_csr_pattern
    use rs_core_kinds, only: rk
    use rs_test_assert, only: run_test, assert_true, assert_equal, fail_count
    use rs_test_random, only: set_random_seed
    use rs_assembly_csr_pattern, only: csr_builder_t, csr_pattern_t
    implicit none
    private

    public :: run_all_tests

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call set_random_seed(8191, 17)
        call run_test('hand_pattern', test_hand_pattern)
        call run_test('hand_positions', test_hand_positions)
        call run_test('hand_zero_based', test_hand_zero_based)
        call run_test('empty_rows_and_builder', test_empty_rows_and_builder)
        call run_test('builder_reuse', test_builder_reuse)
        call run_test('random_blocks_against_dense', test_random_blocks_against_dense)
    end subroutine run_all_tests

    ! Four rows:
    !   block A  rows [2, 1] x cols [3, 1]               -> (2,3) (1,3) (2,1) (1,1)
    !   block B  rows [2, 0, 4] x cols [1, -1, 2]        -> (2,1) again, (4,1) (2,2) (4,2);
    !                                                       row 0 and column -1 skipped
    !   block C  rows [3, 4] x cols [4, 3], mask diagonal -> (3,4) (4,3); (4,4), (3,3) masked
    !   block A again                                    -> duplicates only
    ! Pattern: row 1 {1, 3}, row 2 {1, 2, 3}, row 3 {4}, row 4 {1, 2, 3}; nnz 9.
    subroutine hand_pattern(pattern)
        type(csr_pattern_t), intent(out) :: pattern
        type(csr_builder_t) :: builder
        integer :: rows_a(2), cols_a(2), rows_b(3), cols_b(3), rows_c(2), cols_c(2)
        logical :: mask(2, 2)
        rows_a = [2, 1]
        cols_a = [3, 1]
        rows_b = [2, 0, 4]
        cols_b = [1, -1, 2]
        rows_c = [3, 4]
        cols_c = [4, 3]
        mask = .false.
        mask(1, 1) = .true.
        mask(2, 2) = .true.
        call builder%init(4, 4)
        call builder%add_block(rows_a, cols_a)
        call builder%add_block(rows_b, cols_b)
        call builder%add_block(rows_c, cols_c, mask)
        call builder%add_block(rows_a, cols_a)
        call builder%build(pattern)
    end subroutine hand_pattern

    subroutine test_hand_pattern()
        type(csr_pattern_t) :: p
        integer :: row_ptr(5), cols(9)
        call hand_pattern(p)
        row_ptr = [1, 3, 6, 7, 10]
        cols = [1, 3, 1, 2, 3, 4, 1, 2, 3]
        CHECK_EQUAL(p%n_rows, 4, 'n_rows')
        CHECK_EQUAL(p%nnz(), 9, 'nnz')
        CHECK_EQUAL(size(p%row_ptr), 5, 'row_ptr size')
        CHECK_EQUAL(size(p%cols), 9, 'cols size')
        if (fail_count() > 0) return
        CHECK_TRUE(all(p%row_ptr == row_ptr), 'row_ptr')
        CHECK_TRUE(all(p%cols == cols), 'cols: sorted and unique per row')
    end subroutine test_hand_pattern

    subroutine test_hand_positions()
        type(csr_pattern_t) :: p
        integer :: k, r
        call hand_pattern(p)
        CHECK_EQUAL(p%position(1, 1), 1, '(1,1)')
        CHECK_EQUAL(p%position(1, 3), 2, '(1,3)')
        CHECK_EQUAL(p%position(2, 1), 3, '(2,1)')
        CHECK_EQUAL(p%position(2, 2), 4, '(2,2)')
        CHECK_EQUAL(p%position(2, 3), 5, '(2,3)')
        CHECK_EQUAL(p%position(3, 4), 6, '(3,4)')
        CHECK_EQUAL(p%position(4, 1), 7, '(4,1)')
        CHECK_EQUAL(p%position(4, 2), 8, '(4,2)')
        CHECK_EQUAL(p%position(4, 3), 9, '(4,3)')
        CHECK_EQUAL(p%position(1, 2), 0, 'absent (1,2)')
        CHECK_EQUAL(p%position(1, 4), 0, 'absent (1,4): past the last column of the row')
        CHECK_EQUAL(p%position(3, 3), 0, 'masked (3,3)')
        CHECK_EQUAL(p%position(4, 4), 0, 'masked (4,4)')
        CHECK_EQUAL(p%position(3, 1), 0, 'absent (3,1): before the only column of the row')
        CHECK_EQUAL(p%position(2, 5), 0, 'column beyond the matrix')
        CHECK_EQUAL(p%position(0, 1), 0, 'row 0')
        CHECK_EQUAL(p%position(1, 0), 0, 'column 0')
        CHECK_EQUAL(p%position(-1, 2), 0, 'negative row')
        CHECK_EQUAL(p%position(2, -1), 0, 'negative column (skipped in block B)')
        CHECK_EQUAL(p%position(5, 1), 0, 'row beyond the matrix')
        CHECK_EQUAL(p%position(100, 1), 0, 'row far beyond the matrix')
        ! Every stored entry is found at its own index.
        do r = 1, p%n_rows
            do k = p%row_ptr(r), p%row_ptr(r + 1) - 1
                CHECK_EQUAL(p%position(r, p%cols(k)), k, 'stored entry found')
            end do
        end do
    end subroutine test_hand_positions

    subroutine test_hand_zero_based()
        type(csr_pattern_t) :: p
        integer, allocatable :: row_ptr(:), cols(:)
        integer :: expected_ptr(5), expected_cols(9)
        call hand_pattern(p)
        call p%zero_based(row_ptr, cols)
        expected_ptr = [0, 2, 5, 6, 9]
        expected_cols = [0, 2, 0, 1, 2, 3, 0, 1, 2]
        CHECK_EQUAL(size(row_ptr), 5, 'row_ptr size')
        CHECK_EQUAL(size(cols), 9, 'cols size')
        if (fail_count() > 0) return
        CHECK_TRUE(all(row_ptr == expected_ptr), '0-based row_ptr')
        CHECK_TRUE(all(cols == expected_cols), '0-based cols')
        CHECK_TRUE(all(p%row_ptr == expected_ptr + 1), 'the pattern itself stays 1-based')
    end subroutine test_hand_zero_based

    ! Rows without couplings have row_ptr(r + 1) = row_ptr(r); a builder without any pair (or
    ! with only skipped or masked ones) gives nnz 0.
    subroutine test_empty_rows_and_builder()
        type(csr_builder_t) :: builder
        type(csr_pattern_t) :: p
        integer :: rows(2), cols(2), zero_rows(2)
        logical :: mask(2, 2)
        rows = [2, 5]
        cols = [6, 1]
        call builder%init(6, 0)
        call builder%add_block(rows, cols)
        call builder%build(p)
        CHECK_EQUAL(p%nnz(), 4, 'nnz')
        CHECK_EQUAL(size(p%row_ptr), 7, 'row_ptr size')
        if (size(p%row_ptr) /= 7) return
        CHECK_EQUAL(p%row_ptr(2) - p%row_ptr(1), 0, 'row 1 empty')
        CHECK_EQUAL(p%row_ptr(3) - p%row_ptr(2), 2, 'row 2 has two')
        CHECK_EQUAL(p%row_ptr(6) - p%row_ptr(3), 2, 'rows 3 and 4 empty, row 5 has two')
        CHECK_EQUAL(p%row_ptr(7) - p%row_ptr(6), 0, 'row 6 empty')
        CHECK_EQUAL(p%position(1, 1), 0, 'empty row: nothing found')
        CHECK_EQUAL(p%position(6, 6), 0, 'empty last row: nothing found')
        CHECK_EQUAL(p%cols(p%position(5, 1)), 1, 'sorted: (5,1)')
        CHECK_EQUAL(p%position(5, 6), p%position(5, 1) + 1, 'sorted: (5,6) after (5,1)')

        call builder%init(3, 10)
        call builder%build(p)
        CHECK_EQUAL(p%nnz(), 0, 'no pairs: nnz 0')
        CHECK_TRUE(all(p%row_ptr == 1), 'no pairs: all rows empty')
        CHECK_EQUAL(p%position(2, 2), 0, 'no pairs: nothing found')

        zero_rows = [0, -3]
        mask = .false.
        call builder%init(3, 10)
        call builder%add_block(zero_rows, cols)
        call builder%add_block(rows(1:1), zero_rows)
        call builder%add_block(rows, cols, mask)
        call builder%build(p)
        CHECK_EQUAL(p%nnz(), 0, 'only skipped and masked entries: nnz 0')
    end subroutine test_empty_rows_and_builder

    ! `build` frees the pair lists; `init` makes the builder usable again, starting empty.
    subroutine test_builder_reuse()
        type(csr_builder_t) :: builder
        type(csr_pattern_t) :: first, second
        integer :: a(2), b(1)
        a = [1, 2]
        b = [3]
        call builder%init(3, 1)
        call builder%add_block(a, a)
        call builder%build(first)
        CHECK_EQUAL(first%nnz(), 4, 'first pattern')
        call builder%init(3, 1)
        call builder%add_block(b, b)
        call builder%build(second)
        CHECK_EQUAL(second%nnz(), 1, 'second pattern holds only its own pair')
        CHECK_EQUAL(second%position(3, 3), 1, '(3,3) in the second')
        CHECK_EQUAL(second%position(1, 1), 0, '(1,1) not carried over')
        CHECK_EQUAL(first%position(2, 2), 4, 'the first pattern is unchanged')
    end subroutine test_builder_reuse

    !> A random integer in [low, high].
    integer function random_in(low, high)
        integer, intent(in) :: low, high
        real(rk) :: u
        call random_number(u)
        random_in = low + min(high - low, int(u * real(high - low + 1, rk)))
    end function random_in

    ! Random blocks of 1 to 7 rows and columns drawn from [-2, n] (repeats and entries <= 0
    ! included), half of them masked at random; the builder starts with room for one pair, so
    ! its lists grow many times. The pattern must be exactly the dense matrix of the couplings:
    ! row lengths, sorted columns, every (i, j) found iff coupled, at an index inside its row,
    ! and the 0-based arrays built from the dense matrix.
    subroutine test_random_blocks_against_dense()
        integer, parameter :: n = 37, n_trials = 5
        logical :: dense(n, n)
        type(csr_builder_t) :: builder
        type(csr_pattern_t) :: p
        integer, allocatable :: rows(:), cols(:), row_ptr0(:), cols0(:), expected_cols0(:)
        logical, allocatable :: mask(:, :)
        real(rk), allocatable :: u(:, :)
        integer :: trial, b, i, j, k, pos, expected_nnz
        do trial = 1, n_trials
            dense = .false.
            call builder%init(n, 1)
            do b = 1, 10 * trial
                rows = [(random_in(-2, n), i = 1, random_in(1, 7))]
                cols = [(random_in(-2, n), i = 1, random_in(1, 7))]
                if (random_in(0, 1) == 1) then
                    allocate(u(size(rows), size(cols)))
                    call random_number(u)
                    mask = u < 0.5_rk
                    deallocate(u)
                    call builder%add_block(rows, cols, mask)
                else
                    mask = spread(spread(.true., 1, size(rows)), 2, size(cols))
                    call builder%add_block(rows, cols)
                end if
                do j = 1, size(cols)
                    do i = 1, size(rows)
                        if (rows(i) >= 1 .and. cols(j) >= 1 .and. mask(i, j)) dense(rows(i), cols(j)) = .true.
                    end do
                end do
            end do
            call builder%build(p)
            expected_nnz = count(dense)
            CHECK_EQUAL(p%n_rows, n, 'n_rows')
            CHECK_EQUAL(p%nnz(), expected_nnz, 'nnz = number of coupled pairs')
            CHECK_EQUAL(size(p%cols), expected_nnz, 'cols size')
            CHECK_EQUAL(p%row_ptr(1), 1, 'row_ptr starts at 1')
            if (fail_count() > 0) return
            do i = 1, n
                CHECK_EQUAL(p%row_ptr(i + 1) - p%row_ptr(i), count(dense(i, :)), 'row length')
                do k = p%row_ptr(i) + 1, p%row_ptr(i + 1) - 1
                    CHECK_TRUE(p%cols(k) > p%cols(k - 1), 'row sorted and unique')
                end do
                CHECK_EQUAL(p%position(i, 0), 0, 'column 0 not found')
                CHECK_EQUAL(p%position(i, -1), 0, 'column -1 not found')
                do j = 1, n
                    pos = p%position(i, j)
                    CHECK_EQUAL(pos > 0, dense(i, j), 'found iff coupled')
                    if (pos > 0) then
                        CHECK_TRUE(pos >= p%row_ptr(i) .and. pos < p%row_ptr(i + 1), 'index inside its row')
                        CHECK_EQUAL(p%cols(pos), j, 'index holds the column')
                    end if
                end do
            end do
            CHECK_EQUAL(p%position(n + 1, 1), 0, 'row n + 1 not found')
            ! 0-based arrays against the dense matrix, row by row.
            call p%zero_based(row_ptr0, cols0)
            expected_cols0 = [integer ::]
            do i = 1, n
                CHECK_EQUAL(row_ptr0(i), size(expected_cols0), '0-based row_ptr')
                expected_cols0 = [expected_cols0, pack([(j - 1, j = 1, n)], dense(i, :))]
            end do
            CHECK_EQUAL(row_ptr0(n + 1), size(expected_cols0), '0-based row_ptr: end')
            CHECK_EQUAL(size(cols0), size(expected_cols0), '0-based cols size')
            if (size(cols0) == size(expected_cols0)) then
                CHECK_TRUE(all(cols0 == expected_cols0), '0-based cols')
            end if
        end do
    end subroutine test_random_blocks_against_dense

end module rs_test_assembly_csr_pattern

!> Test program: runs the tests of rs_test_assembly_csr_pattern; exits non-zero if any failed.
program test_csr_pattern
    use rs_test_assembly_csr_pattern, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_csr_pattern
