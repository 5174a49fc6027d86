#include "rs_assert.h"
!> Unit tests of rs_io_namelist_lexer (split_namelist): groups with their lines, assignments
!> with lines, lower-case names and subscripts, value counts with repeat counts, comments
!> (and "!" or "/" inside quoted strings, which neither start a comment nor end a group),
!> multi-line values, the "&end" terminator, CRLF line ends, and the error messages for text
!> outside groups, an unterminated group or string, "=" with no name and a missing group name.
module rs_test_io_namelist_lexer
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_list_t
    use rs_test_assert, only: run_test, assert_true, assert_equal, assert_contains, assert_close
    use rs_io_namelist_lexer, only: assignment_t, group_chunk_t, split_namelist
    implicit none
    private

    public :: run_all_tests

    character(len=*), parameter :: nl = new_line('a')
    character(len=*), parameter :: cr = achar(13)
    character(len=*), parameter :: tab = achar(9)

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('empty_and_comment_only', test_empty_and_comment_only)
        call run_test('groups_and_lines', test_groups_and_lines)
        call run_test('names_targets_subscripts', test_names_targets_subscripts)
        call run_test('value_counts', test_value_counts)
        call run_test('comments', test_comments)
        call run_test('quotes_protect_comment_and_end', test_quotes_protect_comment_and_end)
        call run_test('multi_line_values', test_multi_line_values)
        call run_test('end_terminator', test_end_terminator)
        call run_test('groups_on_one_line', test_groups_on_one_line)
        call run_test('crlf_and_tabs', test_crlf_and_tabs)
        call run_test('error_text_outside', test_error_text_outside)
        call run_test('error_unterminated_group', test_error_unterminated_group)
        call run_test('error_unterminated_string', test_error_unterminated_string)
        call run_test('error_equals_without_name', test_error_equals_without_name)
        call run_test('error_equals_after_blank', test_error_equals_after_blank)
        call run_test('error_group_name_missing', test_error_group_name_missing)
        call run_test('error_junk_before_assignment', test_error_junk_before_assignment)
        call run_test('errors_are_appended', test_errors_are_appended)
    end subroutine run_all_tests

    !> Check the number of chunks and, when it is right, return .true.
    logical function has_chunks(chunks, n) result(ok)
        type(group_chunk_t), intent(in) :: chunks(:)
        integer, intent(in) :: n
        CHECK_EQUAL(size(chunks), n, 'number of groups')
        ok = size(chunks) == n
    end function has_chunks

    !> Check the number of assignments of a chunk and, when it is right, return .true.
    logical function has_assignments(chunk, n) result(ok)
        type(group_chunk_t), intent(in) :: chunk
        integer, intent(in) :: n
        CHECK_EQUAL(size(chunk%assignments), n, 'number of assignments of &' // chunk%name)
        ok = size(chunk%assignments) == n
    end function has_assignments

    !> Check every field of one assignment.
    subroutine check_assignment(a, target, name, subscripted, value, line, n_values)
        type(assignment_t), intent(in) :: a
        character(len=*), intent(in) :: target, name, value
        logical, intent(in) :: subscripted
        integer, intent(in) :: line, n_values
        CHECK_EQUAL(a%target, target, 'target')
        CHECK_EQUAL(a%name, name, 'name of ' // target)
        CHECK_EQUAL(a%subscripted, subscripted, 'subscripted ' // target)
        CHECK_EQUAL(a%value, value, 'value of ' // target)
        CHECK_EQUAL(a%line, line, 'line of ' // target)
        CHECK_EQUAL(a%n_values, n_values, 'number of values of ' // target)
    end subroutine check_assignment

    subroutine test_empty_and_comment_only()
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: errors
        call split_namelist('', 'f.nml', chunks, errors)
        CHECK_EQUAL(errors%count, 0, 'empty text: no error')
        CHECK_EQUAL(size(chunks), 0, 'empty text: no group')
        call split_namelist('! only a comment & / =' // nl // '   ' // nl // '! another' // nl, &
            'f.nml', chunks, errors)
        CHECK_EQUAL(errors%count, 0, 'comments only: no error')
        CHECK_EQUAL(size(chunks), 0, 'comments only: no group')
    end subroutine test_empty_and_comment_only

    subroutine test_groups_and_lines()
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        text = '! header comment' // nl // &                    ! line 1
            "&Run title = 'x' /" // nl // &                     ! line 2
            nl // &                                             ! line 3
            '&TIME' // nl // &                                  ! line 4
            '    t_end = 1.0' // nl // &                        ! line 5
            '    dt = 0.1 /' // nl // &                         ! line 6
            '&rod /' // nl                                      ! line 7
        call split_namelist(text, 'f.nml', chunks, errors)
        CHECK_EQUAL(errors%count, 0, 'no error')
        if (.not. has_chunks(chunks, 3)) return
        CHECK_EQUAL(chunks(1)%name, 'run', 'group name folded to lower case')
        CHECK_EQUAL(chunks(2)%name, 'time', 'second group')
        CHECK_EQUAL(chunks(3)%name, 'rod', 'third group')
        CHECK_EQUAL(chunks(1)%line, 2, 'line of &run')
        CHECK_EQUAL(chunks(2)%line, 4, 'line of &time')
        CHECK_EQUAL(chunks(3)%line, 7, 'line of &rod')
        CHECK_EQUAL(size(chunks(3)%assignments), 0, 'empty group')
        if (has_assignments(chunks(1), 1)) then
            call check_assignment(chunks(1)%assignments(1), 'title', 'title', .false., "'x'", 2, 1)
        end if
        if (has_assignments(chunks(2), 2)) then
            call check_assignment(chunks(2)%assignments(1), 't_end', 't_end', .false., '1.0', 5, 1)
            call check_assignment(chunks(2)%assignments(2), 'dt', 'dt', .false., '0.1', 6, 1)
        end if
    end subroutine test_groups_and_lines

    ! Targets keep their spelling (blanks removed); names are lower case without subscript.
    subroutine test_names_targets_subscripts()
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: errors
        call split_namelist('&rod N_Elements = 4, EI1=2.0, Start ( 2 ) = 1.5,' // nl // &
            '  table_times(3)=7, r%x = 1 /', 'f.nml', chunks, errors)
        CHECK_EQUAL(errors%count, 0, 'no error')
        if (.not. has_chunks(chunks, 1)) return
        if (.not. has_assignments(chunks(1), 5)) return
        call check_assignment(chunks(1)%assignments(1), 'N_Elements', 'n_elements', .false., &
            '4', 1, 1)
        call check_assignment(chunks(1)%assignments(2), 'EI1', 'ei1', .false., '2.0', 1, 1)
        call check_assignment(chunks(1)%assignments(3), 'Start(2)', 'start', .true., '1.5', 1, 1)
        call check_assignment(chunks(1)%assignments(4), 'table_times(3)', 'table_times', .true., &
            '7', 2, 1)
        call check_assignment(chunks(1)%assignments(5), 'r%x', 'r%x', .false., '1', 2, 1)
    end subroutine test_names_targets_subscripts

    ! Separators are commas and blanks outside quotes; r*v counts r values.
    subroutine test_value_counts()
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: errors
        integer, parameter :: expected(10) = [3, 3, 4, 1, 1, 2, 1, 11, 0, 2]
        character(len=:), allocatable :: name
        integer :: k
        call split_namelist("&g a = 1, 2, 3, b = 3*0.0, c = 1 2*5, 7, d = 'x, y'," // &
            " e = 'it''s', f = 2*'a b', g = .true., h = 10*1.0 1.0, i = , j = 'p' ""q"" /", &
            'f.nml', chunks, errors)
        CHECK_EQUAL(errors%count, 0, 'no error')
        if (.not. has_chunks(chunks, 1)) return
        if (.not. has_assignments(chunks(1), size(expected))) return
        do k = 1, size(expected)
            name = chunks(1)%assignments(k)%name
            CHECK_EQUAL(chunks(1)%assignments(k)%n_values, expected(k), 'count of ' // name)
        end do
        CHECK_EQUAL(chunks(1)%assignments(1)%value, '1, 2, 3', 'value text of a')
        CHECK_EQUAL(chunks(1)%assignments(2)%value, '3*0.0', 'value text of b')
        CHECK_EQUAL(chunks(1)%assignments(4)%value, "'x, y'", 'quoted value text of d')
        CHECK_EQUAL(chunks(1)%assignments(5)%value, "'it''s'", 'doubled quote kept')
        CHECK_EQUAL(chunks(1)%assignments(9)%value, '', 'empty value')
    end subroutine test_value_counts

    ! "!" starts a comment to the end of the line; a "/" or "=" in a comment is ignored.
    subroutine test_comments()
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        text = '&g a = 1 ! one / not the end' // nl // &
            '! b = 2 /' // nl // &
            '   c = 3, ! &fake x = 1 /' // nl // &
            '   d = 4 /   ! after the group' // nl // &
            '! &h y = 5 /' // nl
        call split_namelist(text, 'f.nml', chunks, errors)
        CHECK_EQUAL(errors%count, 0, 'no error')
        if (.not. has_chunks(chunks, 1)) return
        if (.not. has_assignments(chunks(1), 3)) return
        call check_assignment(chunks(1)%assignments(1), 'a', 'a', .false., '1', 1, 1)
        call check_assignment(chunks(1)%assignments(2), 'c', 'c', .false., '3', 3, 1)
        call check_assignment(chunks(1)%assignments(3), 'd', 'd', .false., '4', 4, 1)
    end subroutine test_comments

    subroutine test_quotes_protect_comment_and_end()
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        text = "&run title = 'a ! b / c', seed = 2 /" // nl // &
            '&output path = "out/x!y.h5", stride = 3 /' // nl // &
            "&solver petsc_options = 'it''s / -a ! b' /" // nl
        call split_namelist(text, 'f.nml', chunks, errors)
        CHECK_EQUAL(errors%count, 0, 'no error')
        if (.not. has_chunks(chunks, 3)) return
        if (has_assignments(chunks(1), 2)) then
            call check_assignment(chunks(1)%assignments(1), 'title', 'title', .false., &
                "'a ! b / c'", 1, 1)
            call check_assignment(chunks(1)%assignments(2), 'seed', 'seed', .false., '2', 1, 1)
        end if
        if (has_assignments(chunks(2), 2)) then
            call check_assignment(chunks(2)%assignments(1), 'path', 'path', .false., &
                '"out/x!y.h5"', 2, 1)
            call check_assignment(chunks(2)%assignments(2), 'stride', 'stride', .false., '3', 2, 1)
        end if
        if (has_assignments(chunks(3), 1)) then
            call check_assignment(chunks(3)%assignments(1), 'petsc_options', 'petsc_options', &
                .false., &
                "'it''s / -a ! b'", 3, 1)
        end if
    end subroutine test_quotes_protect_comment_and_end

    ! A value over several lines is one line of text; the assignment has the line of its name.
    subroutine test_multi_line_values()
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        real(rk), parameter :: expected(3) = [1.0_rk, 2.0_rk, 3.0_rk]
        real(rk) :: numbers(3)
        integer :: ios
        text = '&rod' // nl // &
            '    start = 1.0,   ! x' // nl // &
            '            2.0,' // nl // &
            nl // &
            '            3.0' // nl // &
            '    d1 = 0, 1,' // nl // &
            '         0 /' // nl
        call split_namelist(text, 'f.nml', chunks, errors)
        CHECK_EQUAL(errors%count, 0, 'no error')
        if (.not. has_chunks(chunks, 1)) return
        if (.not. has_assignments(chunks(1), 2)) return
        associate (start => chunks(1)%assignments(1), d1 => chunks(1)%assignments(2))
            CHECK_EQUAL(start%line, 2, 'line of the name')
            CHECK_EQUAL(start%n_values, 3, 'three values over four lines')
            CHECK_EQUAL(index(start%value, nl), 0, 'no newline in the value')
            CHECK_EQUAL(index(start%value, '!'), 0, 'no comment in the value')
            read(start%value, *, iostat=ios) numbers
            CHECK_EQUAL(ios, 0, 'value readable')
            CHECK_CLOSE(numbers, expected, 0.0_rk, 0.0_rk, 'values in order')
            CHECK_EQUAL(d1%line, 6, 'line of d1')
            CHECK_EQUAL(d1%n_values, 3, 'd1 over two lines')
        end associate
    end subroutine test_multi_line_values

    ! "&end" (any case) closes a group like "/".
    subroutine test_end_terminator()
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        text = '&time t_end = 1' // nl // &
            '&end' // nl // &
            '&rod n = 2 &END' // nl // &
            "&bc kind = 'x' /" // nl
        call split_namelist(text, 'f.nml', chunks, errors)
        CHECK_EQUAL(errors%count, 0, 'no error')
        if (.not. has_chunks(chunks, 3)) return
        CHECK_EQUAL(chunks(1)%name, 'time', 'first group')
        CHECK_EQUAL(chunks(2)%name, 'rod', 'second group')
        CHECK_EQUAL(chunks(3)%name, 'bc', 'third group')
        CHECK_EQUAL(chunks(3)%line, 4, 'line after two &end groups')
        if (has_assignments(chunks(1), 1)) then
            call check_assignment(chunks(1)%assignments(1), 't_end', 't_end', .false., '1', 1, 1)
        end if
        if (has_assignments(chunks(2), 1)) then
            call check_assignment(chunks(2)%assignments(1), 'n', 'n', .false., '2', 3, 1)
        end if
    end subroutine test_end_terminator

    subroutine test_groups_on_one_line()
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: errors
        call split_namelist('&a x = 1 / &b y = 2, z = 3 /&c/', 'f.nml', chunks, errors)
        CHECK_EQUAL(errors%count, 0, 'no error')
        if (.not. has_chunks(chunks, 3)) return
        CHECK_EQUAL(chunks(2)%name, 'b', 'second group')
        CHECK_EQUAL(chunks(3)%name, 'c', 'third group')
        CHECK_EQUAL(chunks(3)%line, 1, 'all on line 1')
        CHECK_EQUAL(size(chunks(2)%assignments), 2, 'two assignments in &b')
        CHECK_EQUAL(size(chunks(3)%assignments), 0, 'no assignment in &c')
    end subroutine test_groups_on_one_line

    ! Windows line ends and tabs are blanks; lines are counted at LF.
    subroutine test_crlf_and_tabs()
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        text = '&a x = 1 /' // cr // nl // &
            '&b' // cr // nl // &
            tab // 'y' // tab // '=' // tab // '2,' // cr // nl // &
            tab // '  3 /' // cr // nl
        call split_namelist(text, 'f.nml', chunks, errors)
        CHECK_EQUAL(errors%count, 0, 'no error')
        if (.not. has_chunks(chunks, 2)) return
        CHECK_EQUAL(chunks(2)%line, 2, 'line of &b')
        if (has_assignments(chunks(2), 1)) then
            call check_assignment(chunks(2)%assignments(1), 'y', 'y', .false., '2,     3', 3, 2)
        end if
    end subroutine test_crlf_and_tabs

    ! One message per line of stray text, with its line; the groups are still split.
    subroutine test_error_text_outside()
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        character(len=*), parameter :: outside = 'text outside a namelist group: '
        text = 'junk line' // nl // &
            '&a x = 1 /' // nl // &
            'more junk here' // nl
        call split_namelist(text, 'f.nml', chunks, errors)
        CHECK_EQUAL(errors%count, 2, 'one error per line')
        CHECK_CONTAINS(errors%joined(), 'f.nml:1: ' // outside // '"junk line"', 'line 1')
        CHECK_CONTAINS(errors%joined(), 'f.nml:3: ' // outside // '"more junk here"', 'line 3')
        CHECK_TRUE(has_chunks(chunks, 1), 'the group between is split')
    end subroutine test_error_text_outside

    subroutine test_error_unterminated_group()
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: errors
        call split_namelist('&a x = 1 /' // nl // '&b' // nl // '  y = 2' // nl, 'f.nml', chunks, &
            errors)
        CHECK_EQUAL(errors%count, 1, 'one error')
        CHECK_EQUAL(errors%joined(), 'f.nml:2: &b is not closed by "/"', 'message with the line')
    end subroutine test_error_unterminated_group

    ! The whole text is checked for an open quote before anything else (DESIGN.md 6).
    subroutine test_error_unterminated_string()
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: errors
        call split_namelist("&a x = 1 /" // nl // "&b s = 'abc /" // nl, 'f.nml', chunks, errors)
        CHECK_EQUAL(errors%count, 1, 'one error')
        CHECK_CONTAINS(errors%joined(), 'f.nml: a quoted string is not closed', 'message')
        CHECK_EQUAL(size(chunks), 0, 'no groups')
        call split_namelist('&b s = "it''s" /' // nl // '&c t = "x /', 'f.nml', chunks, errors)
        CHECK_EQUAL(errors%count, 2, 'an open double quote too')
    end subroutine test_error_unterminated_string

    ! "=" right after a separator, with no variable name before it.
    subroutine test_error_equals_without_name()
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: errors
        call split_namelist('&a x = 1,= 2 /', 'f.nml', chunks, errors)
        CHECK_EQUAL(errors%count, 1, 'one error')
        CHECK_EQUAL(errors%joined(), 'f.nml:1: &a: "=" without a variable name before it', 'text')
        if (has_chunks(chunks, 1)) then
            CHECK_EQUAL(size(chunks(1)%assignments), 1, 'only x = 1 is an assignment')
        end if
    end subroutine test_error_equals_without_name

    ! The same error when blanks or a line break come before the "=": the lexer must neither
    ! stay silent nor produce an assignment without a name (the reader would then report an
    ! unknown variable "").
    subroutine test_error_equals_after_blank()
        character(len=*), parameter :: cases(3) = [character(len=24) :: '&a x = 1, = 2 /', &
            '&a = 1 /', '&a x = 1' // nl // ' = 2 /']
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: errors
        integer :: i, k, name_length
        do i = 1, size(cases)
            errors = error_list_t()
            call split_namelist(trim(cases(i)), 'f.nml', chunks, errors)
            CHECK_CONTAINS(errors%joined(), ': &a: "=" without a variable name', trim(cases(i)))
            if (size(chunks) == 1) then
                do k = 1, size(chunks(1)%assignments)
                    name_length = len(chunks(1)%assignments(k)%name)
                    CHECK_TRUE(name_length > 0, 'no nameless assignment: ' // trim(cases(i)))
                end do
            end if
        end do
    end subroutine test_error_equals_after_blank

    subroutine test_error_group_name_missing()
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: errors
        call split_namelist(nl // '& x = 1 /', 'f.nml', chunks, errors)
        CHECK_TRUE(errors%count >= 1, 'an error')
        CHECK_CONTAINS(errors%joined(), 'f.nml:2: a group name must follow "&"', 'message')
    end subroutine test_error_group_name_missing

    subroutine test_error_junk_before_assignment()
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: errors
        call split_namelist('&time' // nl // ' junk t_end = 1 /', 'f.nml', chunks, errors)
        CHECK_EQUAL(errors%count, 1, 'one error')
        CHECK_CONTAINS(errors%joined(), ': &time: expected "name = value", found "junk', 'message')
        CHECK_CONTAINS(errors%joined(), 'f.nml:2: ', 'line of the stray word')
    end subroutine test_error_junk_before_assignment

    ! split_namelist adds to the list it is given (errors of a file are collected together).
    subroutine test_errors_are_appended()
        type(group_chunk_t), allocatable :: chunks(:)
        type(error_list_t) :: errors
        call errors%add('earlier problem')
        call split_namelist('stray', 'f.nml', chunks, errors)
        CHECK_EQUAL(errors%count, 2, 'earlier error kept')
        CHECK_CONTAINS(errors%joined(), 'earlier problem' // nl // 'f.nml:1: text', 'order')
    end subroutine test_errors_are_appended

end module rs_test_io_namelist_lexer

!> Test program: runs the tests of rs_test_io_namelist_lexer; exits non-zero if any failed.
program test_namelist_lexer
    use rs_test_io_namelist_lexer, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_namelist_lexer
