!> A small assertion library for rodsolve's test programs, in the spirit of pFUnit (which no
!> package source reachable here provides; DESIGN.md §8).
!>
!> A test program is a list of test procedures run through `run_test`; assertions record
!> failures with file and line (use the macros of include/rs_assert.h, which pass __FILE__ and
!> __LINE__) and the program ends with `finish_tests`, which prints the plain closing line
!> "N passed, M failed" and exits non-zero if any test failed.
!>
!> Closeness: |actual - expected| <= atol + rtol * |expected|, component by component.
module rs_test_assert
    use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
    use rs_core_kinds, only: rk
    implicit none
    private

    public :: run_test, finish_tests, assert_true, assert_close, assert_equal, assert_contains
    public :: fail_count

    abstract interface
        subroutine test_procedure()
        end subroutine test_procedure
    end interface

    !> Compare reals (scalar, vector, matrix) with absolute and relative tolerances.
    interface assert_close
        module procedure assert_close_scalar, assert_close_vector, assert_close_matrix
    end interface assert_close

    !> Compare integers, logicals or strings exactly.
    interface assert_equal
        module procedure assert_equal_int, assert_equal_string, assert_equal_logical
    end interface assert_equal

    integer :: n_passed = 0, n_failed = 0
    integer :: failures_in_current = 0
    character(len=:), allocatable :: current_test

contains

    !> Run one test procedure and count it as passed when it recorded no failure.
    subroutine run_test(name, test)
        character(len=*), intent(in) :: name
        procedure(test_procedure) :: test
        current_test = name
        failures_in_current = 0
        call test()
        if (failures_in_current == 0) then
            n_passed = n_passed + 1
            write(output_unit, '(a)') '[  PASSED  ] ' // name
        else
            n_failed = n_failed + 1
            write(output_unit, '(a,i0,a)') '[  FAILED  ] ' // name // ' (', failures_in_current, &
                ' failed assertions)'
        end if
        flush(output_unit)
    end subroutine run_test

    !> Number of failed assertions in the test that is running.
    integer function fail_count()
        fail_count = failures_in_current
    end function fail_count

    !> Print the closing line and stop with status 1 if any test failed.
    subroutine finish_tests()
        write(output_unit, '(i0,a,i0,a)') n_passed, ' passed, ', n_failed, ' failed'
        flush(output_unit)
        if (n_failed > 0) error stop 1
    end subroutine finish_tests

    subroutine record_failure(message, file, line)
        character(len=*), intent(in) :: message, file
        integer, intent(in) :: line
        failures_in_current = failures_in_current + 1
        if (failures_in_current <= 20) then
            write(error_unit, '(a,":",i0,": ",a,": ",a)') trim(file), line, current_test, message
        else if (failures_in_current == 21) then
            write(error_unit, '(a)') '  (further failures of this test not shown)'
        end if
    end subroutine record_failure

    !> Fail unless `condition` holds.
    subroutine assert_true(condition, message, file, line)
        logical, intent(in) :: condition
        character(len=*), intent(in) :: message, file
        integer, intent(in) :: line
        if (.not. condition) call record_failure('expected true: ' // message, file, line)
    end subroutine assert_true

    subroutine assert_close_scalar(actual, expected, atol, rtol, message, file, line)
        real(rk), intent(in) :: actual, expected, atol, rtol
        character(len=*), intent(in) :: message, file
        integer, intent(in) :: line
        character(len=200) :: text
        if (.not. is_close(actual, expected, atol, rtol)) then
            write(text, '(a,es24.16,a,es24.16,a,es10.3,a,es9.2,a,es9.2)') 'actual ', actual, &
                ' expected ', expected, ' |diff| ', abs(actual - expected), ' atol ', atol, ' rtol ', rtol
            call record_failure(message // ': ' // trim(text), file, line)
        end if
    end subroutine assert_close_scalar

    subroutine assert_close_vector(actual, expected, atol, rtol, message, file, line)
        real(rk), intent(in) :: actual(:), expected(:), atol, rtol
        character(len=*), intent(in) :: message, file
        integer, intent(in) :: line
        character(len=240) :: text
        integer :: i, worst
        if (size(actual) /= size(expected)) then
            write(text, '(a,i0,a,i0)') 'size ', size(actual), ' /= expected size ', size(expected)
            call record_failure(message // ': ' // trim(text), file, line)
            return
        end if
        worst = 0
        do i = 1, size(actual)
            if (.not. is_close(actual(i), expected(i), atol, rtol)) then
                if (worst == 0) then
                    worst = i
                else if (abs(actual(i) - expected(i)) > abs(actual(worst) - expected(worst))) then
                    worst = i
                end if
            end if
        end do
        if (worst > 0) then
            write(text, '(a,i0,a,es24.16,a,es24.16,a,es10.3,a,es9.2,a,es9.2)') 'worst component ', worst, &
                ': actual ', actual(worst), ' expected ', expected(worst), ' |diff| ', &
                abs(actual(worst) - expected(worst)), ' atol ', atol, ' rtol ', rtol
            call record_failure(message // ': ' // trim(text), file, line)
        end if
    end subroutine assert_close_vector

    subroutine assert_close_matrix(actual, expected, atol, rtol, message, file, line)
        real(rk), intent(in) :: actual(:, :), expected(:, :), atol, rtol
        character(len=*), intent(in) :: message, file
        integer, intent(in) :: line
        if (any(shape(actual) /= shape(expected))) then
            call record_failure(message // ': shapes differ', file, line)
            return
        end if
        call assert_close_vector(reshape(actual, [size(actual)]), reshape(expected, [size(expected)]), &
            atol, rtol, message // ' (column-major index)', file, line)
    end subroutine assert_close_matrix

    subroutine assert_equal_int(actual, expected, message, file, line)
        integer, intent(in) :: actual, expected
        character(len=*), intent(in) :: message, file
        integer, intent(in) :: line
        character(len=80) :: text
        if (actual /= expected) then
            write(text, '(a,i0,a,i0)') 'actual ', actual, ' expected ', expected
            call record_failure(message // ': ' // trim(text), file, line)
        end if
    end subroutine assert_equal_int

    subroutine assert_equal_logical(actual, expected, message, file, line)
        logical, intent(in) :: actual, expected
        character(len=*), intent(in) :: message, file
        integer, intent(in) :: line
        if (actual .neqv. expected) call record_failure(message // ': logical values differ', file, line)
    end subroutine assert_equal_logical

    subroutine assert_equal_string(actual, expected, message, file, line)
        character(len=*), intent(in) :: actual, expected
        character(len=*), intent(in) :: message, file
        integer, intent(in) :: line
        if (actual /= expected) call record_failure(message // ': actual "' // actual // &
            '" expected "' // expected // '"', file, line)
    end subroutine assert_equal_string

    !> Fail unless `text` contains `fragment`.
    subroutine assert_contains(text, fragment, message, file, line)
        character(len=*), intent(in) :: text, fragment, message, file
        integer, intent(in) :: line
        if (index(text, fragment) == 0) call record_failure(message // ': "' // fragment // &
            '" not found in "' // text // '"', file, line)
    end subroutine assert_contains

    elemental logical function is_close(actual, expected, atol, rtol)
        real(rk), intent(in) :: actual, expected, atol, rtol
        is_close = abs(actual - expected) <= atol + rtol * abs(expected)
        ! NaN never compares close.
        if (actual /= actual) is_close = .false.
    end function is_close

end module rs_test_assert
