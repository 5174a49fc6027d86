#include "rs_assert.h"
!> Unit tests of rs_io_cli (parse_command_line): the scene file, the actions --check-input,
!> --version, --help/-h and --input-reference, --quiet, PETSc options with their values kept in
!> order, and the errors for an unknown "--" flag, a second scene and a missing scene (an
!> error for run and check, not for --version, --help or --input-reference).
module rs_test_io_cli
    use rs_test_assert, only: run_test, assert_true, assert_equal, assert_contains
    use rs_io_cli, only: cli_t, parse_command_line, usage_text
    implicit none
    private

    public :: run_all_tests

    integer, parameter :: arg_len = 32

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('scene_only', test_scene_only)
        call run_test('actions', test_actions)
        call run_test('quiet', test_quiet)
        call run_test('unknown_flag', test_unknown_flag)
        call run_test('second_scene', test_second_scene)
        call run_test('missing_scene', test_missing_scene)
        call run_test('usage_mentions_flags', test_usage_mentions_flags)
        ! Last: with -fcheck=all a failure here stops the program (see the test).
        call run_test('petsc_options_in_order', test_petsc_options_in_order)
    end subroutine run_all_tests

    !> The command line made of the given words (up to 6).
    function parse(a1, a2, a3, a4, a5, a6) result(cli)
        character(len=*), intent(in), optional :: a1, a2, a3, a4, a5, a6
        type(cli_t) :: cli
        character(len=arg_len) :: words(6)
        integer :: n
        n = 0
        if (present(a1)) call add(a1)
        if (present(a2)) call add(a2)
        if (present(a3)) call add(a3)
        if (present(a4)) call add(a4)
        if (present(a5)) call add(a5)
        if (present(a6)) call add(a6)
        cli = parse_command_line('rodsolve', words(1:n))
    contains
        subroutine add(word)
            character(len=*), intent(in) :: word
            n = n + 1
            words(n) = word
        end subroutine add
    end function parse

    subroutine check_no_error(cli, what)
        type(cli_t), intent(in) :: cli
        character(len=*), intent(in) :: what
        CHECK_EQUAL(cli%error, '', what // ': no error')
    end subroutine check_no_error

    subroutine test_scene_only()
        type(cli_t) :: cli
        cli = parse('input/flying_spaghetti.nml')
        call check_no_error(cli, 'scene only')
        CHECK_EQUAL(trim(cli%action), 'run', 'action')
        CHECK_EQUAL(cli%scene_file, 'input/flying_spaghetti.nml', 'scene file')
        CHECK_EQUAL(cli%program, 'rodsolve', 'program name')
        CHECK_EQUAL(cli%quiet, .false., 'not quiet')
        CHECK_EQUAL(size(cli%petsc_args), 0, 'no PETSc options')
    end subroutine test_scene_only

    subroutine test_actions()
        type(cli_t) :: cli
        cli = parse('--check-input', 'a.nml')
        call check_no_error(cli, '--check-input')
        CHECK_EQUAL(trim(cli%action), 'check', '--check-input')
        CHECK_EQUAL(cli%scene_file, 'a.nml', 'scene with --check-input')
        cli = parse('a.nml', '--check-input')
        CHECK_EQUAL(trim(cli%action), 'check', '--check-input after the scene')
        cli = parse('--version')
        call check_no_error(cli, '--version')
        CHECK_EQUAL(trim(cli%action), 'version', '--version')
        cli = parse('--help')
        call check_no_error(cli, '--help')
        CHECK_EQUAL(trim(cli%action), 'help', '--help')
        cli = parse('-h')
        call check_no_error(cli, '-h')
        CHECK_EQUAL(trim(cli%action), 'help', '-h')
        CHECK_EQUAL(size(cli%petsc_args), 0, '-h is not a PETSc option')
        cli = parse('--input-reference')
        call check_no_error(cli, '--input-reference')
        CHECK_EQUAL(trim(cli%action), 'reference', '--input-reference')
        ! --help wins over --check-input whatever the order.
        cli = parse('--help', '--check-input', 'a.nml')
        CHECK_EQUAL(trim(cli%action), 'help', '--help before --check-input')
        cli = parse('--check-input', 'a.nml', '--help')
        CHECK_EQUAL(trim(cli%action), 'help', '--help after --check-input')
    end subroutine test_actions

    subroutine test_quiet()
        type(cli_t) :: cli
        cli = parse('--quiet', 'a.nml')
        call check_no_error(cli, '--quiet')
        CHECK_EQUAL(cli%quiet, .true., '--quiet')
        CHECK_EQUAL(trim(cli%action), 'run', 'still a run')
        CHECK_EQUAL(cli%scene_file, 'a.nml', 'scene')
    end subroutine test_quiet

    ! Every "-x" starts a PETSc option and the words up to the next "-" are its values; the
    ! order is kept. A "--" flag ends the option, so a scene may follow it. The words here are
    ! shorter than cli_t's petsc_args (any length is allowed by the interface).
    subroutine test_petsc_options_in_order()
        type(cli_t) :: cli
        cli = parse('scene.nml', '-ksp_type', 'gmres', '-snes_monitor')
        call check_no_error(cli, 'scene with options')
        CHECK_EQUAL(cli%scene_file, 'scene.nml', 'scene')
        CHECK_EQUAL(size(cli%petsc_args), 3, 'three PETSc words')
        if (size(cli%petsc_args) == 3) then
            CHECK_EQUAL(trim(cli%petsc_args(1)), '-ksp_type', 'first')
            CHECK_EQUAL(trim(cli%petsc_args(2)), 'gmres', 'its value')
            CHECK_EQUAL(trim(cli%petsc_args(3)), '-snes_monitor', 'flag without value')
        end if
        cli = parse('-snes_rtol', '0', '-mat_mumps_icntl_14', '50', '--quiet', 'b.nml')
        call check_no_error(cli, 'options before the scene')
        CHECK_EQUAL(cli%scene_file, 'b.nml', 'scene after --quiet')
        CHECK_EQUAL(size(cli%petsc_args), 4, 'four PETSc words')
        if (size(cli%petsc_args) == 4) then
            CHECK_EQUAL(trim(cli%petsc_args(2)), '0', 'value of -snes_rtol')
            CHECK_EQUAL(trim(cli%petsc_args(3)), '-mat_mumps_icntl_14', 'second option')
            CHECK_EQUAL(trim(cli%petsc_args(4)), '50', 'its value')
        end if
        cli = parse('-snes_monitor')
        CHECK_EQUAL(cli%error, 'rodsolve: no scene file given', 'PETSc options only')
    end subroutine test_petsc_options_in_order

    subroutine test_unknown_flag()
        type(cli_t) :: cli
        cli = parse('--verbose', 'a.nml')
        CHECK_CONTAINS(cli%error, 'rodsolve: unknown flag --verbose', 'message')
        CHECK_CONTAINS(cli%error, 'rodsolve --help', 'points to --help')
        CHECK_EQUAL(cli%scene_file, 'a.nml', 'scene still found')
        cli = parse('--version', '--bogus')
        CHECK_CONTAINS(cli%error, 'unknown flag --bogus', 'also with --version')
    end subroutine test_unknown_flag

    subroutine test_second_scene()
        type(cli_t) :: cli
        cli = parse('a.nml', 'b.nml')
        CHECK_CONTAINS(cli%error, 'rodsolve: a second scene file "b.nml"', 'message')
        CHECK_EQUAL(cli%scene_file, 'a.nml', 'first scene kept')
        ! Both problems are reported, one per line.
        cli = parse('a.nml', '--nope', 'b.nml')
        CHECK_CONTAINS(cli%error, 'rodsolve: unknown flag --nope', 'first problem')
        CHECK_CONTAINS(cli%error, 'flags)' // new_line('a') // 'rodsolve: a second', 'second line')
    end subroutine test_second_scene

    subroutine test_missing_scene()
        type(cli_t) :: cli
        cli = parse()
        CHECK_EQUAL(cli%error, 'rodsolve: no scene file given', 'empty command line')
        cli = parse('--check-input')
        CHECK_EQUAL(cli%error, 'rodsolve: no scene file given', '--check-input without scene')
        cli = parse('--version')
        CHECK_EQUAL(cli%error, '', '--version needs no scene')
        cli = parse('--help')
        CHECK_EQUAL(cli%error, '', '--help needs no scene')
        cli = parse('--input-reference')
        CHECK_EQUAL(cli%error, '', '--input-reference needs no scene')
    end subroutine test_missing_scene

    ! --help must describe every flag the parser accepts.
    subroutine test_usage_mentions_flags()
        character(len=:), allocatable :: text
        text = usage_text()
        CHECK_CONTAINS(text, '--check-input', 'usage')
        CHECK_CONTAINS(text, '--quiet', 'usage')
        CHECK_CONTAINS(text, '--version', 'usage')
        CHECK_CONTAINS(text, '--input-reference', 'usage')
        CHECK_CONTAINS(text, '--help, -h', 'usage')
    end subroutine test_usage_mentions_flags

end module rs_test_io_cli

!> Test program: runs the tests of rs_test_io_cli; exits non-zero if any failed.
program test_cli
    use rs_test_io_cli, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_cli
