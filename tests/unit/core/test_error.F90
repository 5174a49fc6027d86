#include "rs_assert.h"
!> Unit tests of rs_core_error: set_error fills message, routine, file (made relative to src/ or
!> tests/), line and exit status; describe() formats them; set_petsc_error names the call and
!> code; error_list_t adds, counts and joins messages in order.
module rs_test_core_error
    use rs_test_assert, only: run_test, assert_true, assert_equal, assert_contains
    use rs_core_error, only: error_t, error_list_t, set_error, set_petsc_error, exit_input_error, &
        exit_run_error
    implicit none
    private

    public :: run_all_tests

    character(len=*), parameter :: nl = new_line('a')

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('set_error_fields', test_set_error_fields)
        call run_test('set_error_relative_paths', test_set_error_relative_paths)
        call run_test('set_error_exit_status', test_set_error_exit_status)
        call run_test('set_error_replaces', test_set_error_replaces)
        call run_test('describe_format', test_describe_format)
        call run_test('set_petsc_error', test_set_petsc_error)
        call run_test('error_list_empty', test_error_list_empty)
        call run_test('error_list_add_and_join', test_error_list_add_and_join)
    end subroutine run_all_tests

    subroutine test_set_error_fields()
        type(error_t), allocatable :: err
        CHECK_TRUE(.not. allocated(err), 'unallocated means success')
        call set_error(err, 'matrix is singular', 'factorize', '/home/u/rs/src/solver/lu.F90', 57)
        CHECK_TRUE(allocated(err), 'allocated after set_error')
        if (.not. allocated(err)) return
        CHECK_EQUAL(err%message, 'matrix is singular', 'message')
        CHECK_EQUAL(err%routine, 'factorize', 'routine')
        CHECK_EQUAL(err%file, 'src/solver/lu.F90', 'file relative to src/')
        CHECK_EQUAL(err%line, 57, 'line')
    end subroutine test_set_error_fields

    subroutine test_set_error_relative_paths()
        type(error_t), allocatable :: err
        call set_error(err, 'm', 'r', '/a/b/tests/unit/core/test_error.F90', 1)
        CHECK_EQUAL(err%file, 'tests/unit/core/test_error.F90', 'relative to tests/')
        ! The last "/src/" counts: a checkout below a directory called src.
        call set_error(err, 'm', 'r', '/src/work/src/io/cli.f90', 1)
        CHECK_EQUAL(err%file, 'src/io/cli.f90', 'last /src/ in the path')
        call set_error(err, 'm', 'r', 'cli.f90', 1)
        CHECK_EQUAL(err%file, 'cli.f90', 'a bare file name is kept')
        call set_error(err, 'm', 'r', '/opt/lib/solver.c', 1)
        CHECK_EQUAL(err%file, '/opt/lib/solver.c', 'a path outside src/ and tests/ is kept')
    end subroutine test_set_error_relative_paths

    subroutine test_set_error_exit_status()
        type(error_t), allocatable :: err
        call set_error(err, 'm', 'r', 'f', 1)
        CHECK_EQUAL(err%exit_status, exit_run_error, 'default: run error')
        CHECK_EQUAL(exit_run_error, 1, 'run error status is 1')
        call set_error(err, 'm', 'r', 'f', 1, exit_status=exit_input_error)
        CHECK_EQUAL(err%exit_status, 2, 'input error status is 2 (DESIGN.md 6)')
    end subroutine test_set_error_exit_status

    ! A second set_error on the same object replaces every field (no leftover status).
    subroutine test_set_error_replaces()
        type(error_t), allocatable :: err
        call set_error(err, 'first', 'one', '/x/src/a.f90', 10, exit_status=exit_input_error)
        call set_error(err, 'second', 'two', '/x/src/b.f90', 20)
        CHECK_EQUAL(err%message, 'second', 'message replaced')
        CHECK_EQUAL(err%routine, 'two', 'routine replaced')
        CHECK_EQUAL(err%file, 'src/b.f90', 'file replaced')
        CHECK_EQUAL(err%line, 20, 'line replaced')
        CHECK_EQUAL(err%exit_status, exit_run_error, 'status back to the default')
    end subroutine test_set_error_replaces

    subroutine test_describe_format()
        type(error_t), allocatable :: err
        type(error_t) :: bare
        character(len=*), parameter :: expected = &
            'Newton did not converge (in step, src/solver/ts.F90:123)'
        call set_error(err, 'Newton did not converge', 'step', '/w/src/solver/ts.F90', 123)
        CHECK_EQUAL(err%describe(), expected, 'message (in routine and file:line)')
        bare%message = 'only a message'
        CHECK_EQUAL(bare%describe(), 'only a message', 'no routine: the message alone')
    end subroutine test_describe_format

    subroutine test_set_petsc_error()
        type(error_t), allocatable :: err
        call set_petsc_error(err, 73, 'KSPSolve', 'solve', '/w/src/solver/ksp.F90', 9)
        CHECK_EQUAL(err%message, 'PETSc call KSPSolve failed with error code 73', 'message')
        CHECK_EQUAL(err%routine, 'solve', 'routine')
        CHECK_EQUAL(err%file, 'src/solver/ksp.F90', 'file')
        CHECK_EQUAL(err%line, 9, 'line')
        CHECK_CONTAINS(err%describe(), 'error code 73 (in solve', 'describe')
    end subroutine test_set_petsc_error

    subroutine test_error_list_empty()
        type(error_list_t) :: list
        CHECK_EQUAL(list%count, 0, 'no messages')
        CHECK_EQUAL(list%joined(), '', 'joined text empty')
        CHECK_EQUAL(len(list%joined()), 0, 'joined length 0')
    end subroutine test_error_list_empty

    subroutine test_error_list_add_and_join()
        type(error_list_t) :: list
        character(len=:), allocatable :: expected
        call list%add('a.nml:3: first')
        CHECK_EQUAL(list%count, 1, 'one message')
        CHECK_EQUAL(list%joined(), 'a.nml:3: first', 'one message: no newline')
        call list%add('a.nml:5: second')
        call list%add('two' // nl // 'lines')
        CHECK_EQUAL(list%count, 3, 'a multi-line message counts once')
        expected = 'a.nml:3: first' // nl // 'a.nml:5: second' // nl // 'two' // nl // 'lines'
        CHECK_EQUAL(list%joined(), expected, 'in order and separated by newlines')
        call list%add('')
        CHECK_EQUAL(list%count, 4, 'an empty message still counts')
        CHECK_EQUAL(list%joined(), expected // nl, 'an empty message adds an empty line')
    end subroutine test_error_list_add_and_join

end module rs_test_core_error

!> Test program: runs the tests of rs_test_core_error; exits non-zero if any failed.
program test_error
    use rs_test_core_error, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_error
