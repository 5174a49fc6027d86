#include "rs_assert.h"
!> Unit tests of rs_parallel_mpi_env on 2 ranks: world_size, world_rank and is_root;
!> broadcast_text of a text only the root has (short, empty, 100000 characters, from rank 1,
!> over a text rank 1 already holds) arrives identically; broadcast_flag; any_rank_true; the
!> MPI library version line. Every rank runs every test; the failures of all ranks are summed
!> so that every rank exits non-zero if any rank failed.
module rs_test_parallel_mpi_env
    use mpi
    use rs_test_assert, only: run_test, fail_count, assert_true, assert_equal, assert_contains
    use rs_parallel_mpi_env, only: world_rank, world_size, is_root, broadcast_text, &
        broadcast_flag, any_rank_true, barrier, mpi_library_version
    implicit none
    private

    public :: run_all_tests

contains

    !> Run every test of this file; `n_failed` is the number of tests that failed on this rank.
    subroutine run_all_tests(n_failed)
        integer, intent(out) :: n_failed
        n_failed = 0
        call run('world_size_and_rank', test_world_size_and_rank)
        call run('broadcast_short_text', test_broadcast_short_text)
        call run('broadcast_empty_text', test_broadcast_empty_text)
        call run('broadcast_long_text', test_broadcast_long_text)
        call run('broadcast_text_from_rank_1', test_broadcast_text_from_rank_1)
        call run('broadcast_replaces_text', test_broadcast_replaces_text)
        call run('broadcast_flag', test_broadcast_flag)
        call run('any_rank_true', test_any_rank_true)
        call run('mpi_library_version', test_mpi_library_version)
    contains
        subroutine run(name, test)
            character(len=*), intent(in) :: name
            procedure() :: test
            character(len=16) :: rank
            write(rank, '(a,i0,a)') ' (rank ', world_rank(), ')'
            call run_test(name // trim(rank), test)
            if (fail_count() > 0) n_failed = n_failed + 1
        end subroutine run
    end subroutine run_all_tests

    !> The test text of `n` characters: printable ASCII in a pattern that does not repeat
    !> with a short period, built on each rank independently.
    function pattern(n) result(text)
        integer, intent(in) :: n
        character(len=n) :: text
        integer :: i
        do i = 1, n
            text(i:i) = achar(32 + mod(i * 7919 + (i / 95) * 31, 95))
        end do
    end function pattern

    subroutine test_world_size_and_rank()
        integer :: rank, rank_sum, ierr
        CHECK_EQUAL(world_size(), 2, 'this test runs on 2 ranks')
        rank = world_rank()
        CHECK_TRUE(rank == 0 .or. rank == 1, 'rank 0 or 1')
        call MPI_Allreduce(rank, rank_sum, 1, MPI_INTEGER, MPI_SUM, MPI_COMM_WORLD, ierr)
        CHECK_EQUAL(rank_sum, 1, 'ranks 0 and 1 once each')
        CHECK_EQUAL(is_root(), rank == 0, 'is_root on rank 0 only')
    end subroutine test_world_size_and_rank

    subroutine test_broadcast_short_text()
        character(len=:), allocatable :: text
        character(len=*), parameter :: expected = "&run title = 'x' /" // new_line('a') // &
            '! comment with "quotes"'
        if (world_rank() == 0) text = expected
        call broadcast_text(text, 0)
        CHECK_TRUE(allocated(text), 'allocated on every rank')
        if (.not. allocated(text)) return
        CHECK_EQUAL(len(text), len(expected), 'length')
        CHECK_EQUAL(text, expected, 'content')
    end subroutine test_broadcast_short_text

    subroutine test_broadcast_empty_text()
        character(len=:), allocatable :: text
        if (world_rank() == 0) then
            text = ''
        else
            text = 'stale text on rank 1'
        end if
        call broadcast_text(text, 0)
        CHECK_TRUE(allocated(text), 'allocated')
        if (allocated(text)) then
            CHECK_EQUAL(len(text), 0, 'empty on every rank')
        end if
    end subroutine test_broadcast_empty_text

    subroutine test_broadcast_long_text()
        integer, parameter :: n = 100000
        character(len=:), allocatable :: text, expected
        integer :: first_bad
        expected = pattern(n)
        if (world_rank() == 0) text = expected
        call broadcast_text(text, 0)
        CHECK_TRUE(allocated(text), 'allocated')
        if (.not. allocated(text)) return
        CHECK_EQUAL(len(text), n, 'length 100000')
        if (len(text) /= n) return
        first_bad = first_difference(text, expected)
        CHECK_EQUAL(first_bad, 0, 'first differing character (0: identical)')
    end subroutine test_broadcast_long_text

    pure integer function first_difference(a, b) result(at)
        character(len=*), intent(in) :: a, b
        integer :: i
        at = 0
        do i = 1, min(len(a), len(b))
            if (a(i:i) /= b(i:i)) then
                at = i
                return
            end if
        end do
    end function first_difference

    subroutine test_broadcast_text_from_rank_1()
        character(len=:), allocatable :: text
        character(len=*), parameter :: expected = 'only rank 1 knows this'
        if (world_rank() == 1) text = expected
        call broadcast_text(text, 1)
        CHECK_TRUE(allocated(text), 'allocated')
        if (allocated(text)) then
            CHECK_EQUAL(text, expected, 'text of rank 1 on every rank')
        end if
    end subroutine test_broadcast_text_from_rank_1

    ! A longer text already allocated on the receiving rank is replaced, not overwritten in part.
    subroutine test_broadcast_replaces_text()
        character(len=:), allocatable :: text
        if (world_rank() == 0) then
            text = 'new'
        else
            text = 'an older and much longer text'
        end if
        call broadcast_text(text, 0)
        CHECK_EQUAL(text, 'new', 'replaced')
        CHECK_EQUAL(len(text), 3, 'with the new length')
    end subroutine test_broadcast_replaces_text

    subroutine test_broadcast_flag()
        logical :: flag
        flag = world_rank() == 0
        call broadcast_flag(flag, 0)
        CHECK_EQUAL(flag, .true., 'true from rank 0')
        flag = world_rank() == 0
        call broadcast_flag(flag, 1)
        CHECK_EQUAL(flag, .false., 'false from rank 1')
        flag = world_rank() /= 0
        call broadcast_flag(flag, 0)
        CHECK_EQUAL(flag, .false., 'false from rank 0')
    end subroutine test_broadcast_flag

    subroutine test_any_rank_true()
        CHECK_EQUAL(any_rank_true(world_rank() == 1), .true., 'true on rank 1 only')
        CHECK_EQUAL(any_rank_true(world_rank() == 0), .true., 'true on rank 0 only')
        CHECK_EQUAL(any_rank_true(.false.), .false., 'false everywhere')
        CHECK_EQUAL(any_rank_true(.true.), .true., 'true everywhere')
        call barrier()
    end subroutine test_any_rank_true

    ! DESIGN.md: Open MPI; the version is one line.
    subroutine test_mpi_library_version()
        character(len=:), allocatable :: text
        text = mpi_library_version()
        CHECK_TRUE(len(text) > 0, 'not empty')
        CHECK_CONTAINS(text, 'Open MPI', 'the MPI of DESIGN.md')
        CHECK_EQUAL(index(text, new_line('a')), 0, 'one line')
    end subroutine test_mpi_library_version

end module rs_test_parallel_mpi_env

!> Test program: runs the tests of rs_test_parallel_mpi_env on every rank; every rank exits
!> non-zero if any rank failed.
program test_mpi_env
    use mpi
    use rs_test_parallel_mpi_env, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    integer :: ierr, n_failed, n_failed_all, rank
    call MPI_Init(ierr)
    call MPI_Comm_rank(MPI_COMM_WORLD, rank, ierr)
    call run_all_tests(n_failed)
    call MPI_Allreduce(n_failed, n_failed_all, 1, MPI_INTEGER, MPI_SUM, MPI_COMM_WORLD, ierr)
    call MPI_Finalize(ierr)
    ! Rank 0 prints its summary (and stops with 1 if it failed itself); every rank then stops
    ! with 1 if any rank failed.
    if (rank == 0) call finish_tests()
    if (n_failed_all > 0) then
        if (rank == 0) write(*, '(i0,a)') n_failed_all, ' failed test(s) over all ranks'
        error stop 1
    end if
end program test_mpi_env
