#include "rs_assert.h"
!> Unit tests of rs_io_sweep (and the sweep helpers of rs_model_scene): member counts of product
!> and zip sweeps, member order (first sweep slowest), linspace and logspace values (ends
!> exact), member texts that read back to the swept values bit for bit (a value replaced, an
!> array entry replaced, an item added, a missing single group added), integers written as
!> integers, line numbers kept, the checks of paths and values, and check_sweep_members'
!> report of failing members. The bad scenes of tests/input/bad/sweep_*.nml are not repeated.
module rs_test_io_sweep
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_list_t
    use rs_test_assert, only: run_test, assert_true, assert_equal, assert_contains, assert_close
    use rs_model_scene, only: scene_t, sweep_input_t, sweep_values, sweep_member_indices, &
        max_sweep_members
    use rs_io_input_file, only: parse_scene
    use rs_io_sweep, only: sweep_member_t, sweep_member_count, sweep_members, sweep_member, &
        check_sweep_members
    implicit none
    private

    public :: run_all_tests

    character(len=*), parameter :: nl = new_line('a')

    !> A valid base scene: one rod (line 3), a clamp and a tip load given in full (line 5).
    character(len=*), parameter :: base = &
        '&time t_end = 1, dt = 0.5 /' // nl // &
        "&output path = 'out/keep.h5' /" // nl // &
        "&rod name = 'beam', n_elements = 2, length = 1, EA = 1e4, GA1 = 2e3, GA2 = 3e3," // nl // &
        '     EI1 = 12.5, EI2 = 13.5, GJ = 7, rhoA = 0.5, rhoI1 = 1e-3, rhoI2 = 2e-3 /' // nl // &
        "&load rod = 'beam', where = 'end', force = 0, 2*-1 /" // nl // &
        "&bc rod = 'beam', end = 'start', kind = 'clamped' /" // nl

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('counts_product_and_zip', test_counts_product_and_zip)
        call run_test('member_order_first_slowest', test_member_order_first_slowest)
        call run_test('linspace_and_logspace', test_linspace_and_logspace)
        call run_test('member_text_round_trip', test_member_text_round_trip)
        call run_test('array_entries_and_items', test_array_entries_and_items)
        call run_test('missing_single_group_added', test_missing_single_group_added)
        call run_test('integers_as_integers', test_integers_as_integers)
        call run_test('one_member_equals_all_members', test_one_member_equals_all_members)
        call run_test('path_errors', test_path_errors)
        call run_test('value_errors', test_value_errors)
        call run_test('placement_errors', test_placement_errors)
        call run_test('failing_members_reported', test_failing_members_reported)
        call run_test('line_numbers_kept', test_line_numbers_kept)
    end subroutine run_all_tests

    !> Parse `text` and expect `n_errors` errors (shown on a mismatch).
    subroutine parse(text, scene, errors, n_errors)
        character(len=*), intent(in) :: text
        type(scene_t), intent(out) :: scene
        type(error_list_t), intent(out) :: errors
        integer, intent(in) :: n_errors
        call parse_scene(text, 'sweep.nml', scene, errors)
        CHECK_EQUAL(errors%count, n_errors, 'number of errors; errors: ' // errors%joined())
    end subroutine parse

    !> The members of a valid scene with sweeps; `ok` false (and checks failed) otherwise.
    subroutine members_of(text, scene, members, ok)
        character(len=*), intent(in) :: text
        type(scene_t), intent(out) :: scene
        type(sweep_member_t), allocatable, intent(out) :: members(:)
        logical, intent(out) :: ok
        type(error_list_t) :: errors
        call parse(text, scene, errors, 0)
        ok = errors%count == 0
        if (.not. ok) return
        call sweep_members(text, 'sweep.nml', scene, members, errors)
        CHECK_EQUAL(errors%count, 0, 'members built: ' // errors%joined())
        ok = errors%count == 0
    end subroutine members_of

    !> The scene of a member's text, parsed without errors.
    subroutine member_scene(member, scene, ok)
        type(sweep_member_t), intent(in) :: member
        type(scene_t), intent(out) :: scene
        logical, intent(out) :: ok
        type(error_list_t) :: errors
        call parse_scene(member%text, 'sweep.nml', scene, errors)
        CHECK_EQUAL(errors%count, 0, 'member text parses: ' // errors%joined() // nl // member%text)
        ok = errors%count == 0
        if (ok) then
            CHECK_EQUAL(size(scene%sweeps), 0, 'a member has no &sweep')
        end if
    end subroutine member_scene

    ! 3 x 2 values with a third sweep zipped to the second: 6 members; a zip of the first sweep
    ! is ignored; no &sweep: 0 members.
    subroutine test_counts_product_and_zip()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        call parse(base // "&sweep parameter = 'rod(1)%EI1', values = 1, 2, 3 /" // nl // &
            "&sweep parameter = 'rod(1)%EI2', linspace = 1, 2, 2 /" // nl // &
            "&sweep parameter = 'rod(1)%GJ', values = 5, 6, mode = 'zip' /" // nl, scene, errors, 0)
        CHECK_EQUAL(sweep_member_count(scene), 6, 'product 3 x 2, zip adds none')
        call parse(base // "&sweep parameter = 'rod(1)%EI1', values = 1, 2, 3, mode = 'zip' /" // nl // &
            "&sweep parameter = 'rod(1)%EI2', values = 1, 2, 3, 4 /" // nl, scene, errors, 0)
        CHECK_EQUAL(sweep_member_count(scene), 12, 'the first sweep''s mode is ignored')
        call parse(base, scene, errors, 0)
        CHECK_EQUAL(sweep_member_count(scene), 0, 'no sweep, no members')
    end subroutine test_counts_product_and_zip

    ! Nested loops in file order: the first sweep varies slowest, a zipped sweep with its partner.
    subroutine test_member_order_first_slowest()
        type(scene_t) :: scene
        type(sweep_member_t), allocatable :: members(:)
        real(rk), parameter :: a(3) = [1.0_rk, 2.0_rk, 3.0_rk], b(2) = [10.0_rk, 20.0_rk], &
            c(2) = [5.0_rk, 6.0_rk]
        integer :: id, i, j
        logical :: ok
        call members_of(base // "&sweep parameter = 'rod(1)%EI1', values = 1, 2, 3 /" // nl // &
            "&sweep parameter = 'rod(1)%EI2', values = 10, 20 /" // nl // &
            "&sweep parameter = 'rod(1)%GJ', values = 5, 6, mode = 'zip' /" // nl, scene, members, ok)
        if (.not. ok) return
        CHECK_EQUAL(size(members), 6, 'six members')
        if (size(members) /= 6) return
        id = 0
        do i = 1, 3
            do j = 1, 2
                id = id + 1
                CHECK_EQUAL(members(id)%id, id, 'id')
                CHECK_TRUE(all(members(id)%values == [a(i), b(j), c(j)]), 'values of member ' // achar(48 + id))
                CHECK_TRUE(all(sweep_member_indices(scene%sweeps, id) == [i, j, j]), 'indices')
            end do
        end do
        CHECK_EQUAL(members(1)%parameters(1), 'rod(1)%EI1', 'canonical path 1')
        CHECK_EQUAL(members(1)%parameters(3), 'rod(1)%GJ', 'canonical path 3')
    end subroutine test_member_order_first_slowest

    ! Evenly and geometrically spaced values: the ends exactly as given, the interior to
    ! round-off, whole grids exact.
    subroutine test_linspace_and_logspace()
        type(sweep_input_t) :: sweep
        real(rk), allocatable :: v(:)
        integer :: j
        sweep%linspace = [0.1_rk, 0.7_rk, 7.0_rk]
        v = sweep_values(sweep)
        CHECK_EQUAL(size(v), 7, 'linspace count')
        CHECK_TRUE(v(1) == 0.1_rk .and. v(7) == 0.7_rk, 'linspace ends exact')
        do j = 1, 7
            CHECK_CLOSE(v(j), 0.1_rk * j, 1.0e-15_rk, 0.0_rk, 'linspace value')
        end do
        sweep = sweep_input_t()
        sweep%linspace = [-2.0_rk, 2.0_rk, 5.0_rk]
        v = sweep_values(sweep)
        CHECK_TRUE(all(v == [-2.0_rk, -1.0_rk, 0.0_rk, 1.0_rk, 2.0_rk]), 'whole linspace exact')
        sweep = sweep_input_t()
        sweep%logspace = [1.0e-3_rk, 1.0e3_rk, 7.0_rk]
        v = sweep_values(sweep)
        CHECK_EQUAL(size(v), 7, 'logspace count')
        CHECK_TRUE(v(1) == 1.0e-3_rk .and. v(7) == 1.0e3_rk, 'logspace ends exact')
        do j = 2, 6
            CHECK_CLOSE(v(j), 10.0_rk**(j - 4), 0.0_rk, 1.0e-14_rk, 'logspace value')
            CHECK_CLOSE(v(j) / v(j - 1), 10.0_rk, 0.0_rk, 1.0e-14_rk, 'constant ratio')
        end do
        sweep = sweep_input_t()
        sweep%values(1:3) = [3.0_rk, -1.0_rk, 2.5_rk]
        v = sweep_values(sweep)
        CHECK_TRUE(size(v) == 3 .and. all(v == [3.0_rk, -1.0_rk, 2.5_rk]), 'values as given, in order')
    end subroutine test_linspace_and_logspace

    ! Each member's text reads back to its swept value bit for bit (values that need 17 digits),
    ! starts with its comment line, has no &sweep and keeps the output path.
    subroutine test_member_text_round_trip()
        type(scene_t) :: scene, member
        type(sweep_member_t), allocatable :: members(:)
        real(rk), allocatable :: expected(:)
        integer :: id
        logical :: ok
        call members_of(base // "&sweep parameter = 'Rod(1)%ei1', logspace = 0.3, 70, 9 /" // nl, &
            scene, members, ok)
        if (.not. ok) return
        CHECK_EQUAL(scene%sweeps(1)%parameter, 'rod(1)%EI1', 'canonical spelling resolved')
        expected = sweep_values(scene%sweeps(1))
        CHECK_EQUAL(size(members), 9, 'nine members')
        do id = 1, size(members)
            CHECK_TRUE(members(id)%values(1) == expected(id), 'member value')
            CHECK_TRUE(index(members(id)%text, '! sweep member ') == 1, 'comment line first')
            CHECK_CONTAINS(members(id)%text, ' of 9: rod(1)%EI1 = ', 'comment line names the value')
            call member_scene(members(id), member, ok)
            if (.not. ok) cycle
            CHECK_TRUE(member%rods(1)%EI1 == expected(id), 'EI1 read back bit for bit')
            CHECK_TRUE(member%rods(1)%EI2 == 13.5_rk, 'the rest unchanged')
            CHECK_EQUAL(trim(member%output%path), 'out/keep.h5', 'output path kept')
        end do
        CHECK_TRUE(index(members(1)%text, 'EI1 = 0.3,') > 0, 'base value replaced in place')
        CHECK_TRUE(index(members(1)%text, 'EI1 = 12.5') == 0, 'base value gone')
    end subroutine test_member_text_round_trip

    ! An entry of an array given in full (with a repeat count), an array element and a scalar
    ! the group does not give (added as its last items), and a value replaced in &time.
    subroutine test_array_entries_and_items()
        character(len=:), allocatable :: want
        type(scene_t) :: scene, member
        type(sweep_member_t), allocatable :: members(:)
        logical :: ok
        call members_of(base // "&sweep parameter = 'load(1)%force(3)', values = -7.5 /" // nl // &
            "&sweep parameter = 'load(1)%moment(2)', values = 0.25 /" // nl // &
            "&sweep parameter = 'load(1)%t_on', values = 0.125 /" // nl // &
            "&sweep parameter = 'time%dt', values = 0.1 /" // nl // &
            "&sweep parameter = 'rod(1)%start(2)', values = 3 /" // nl, scene, members, ok)
        if (.not. ok) return
        CHECK_EQUAL(size(members), 1, 'one member')
        CHECK_CONTAINS(members(1)%text, 'force = 0, -1, -7.5', 'entry 3 of "0, 2*-1" replaced')
        want = "'end', force = 0, -1, -7.5, moment(2) = 0.25, t_on = 0.125 /"
        CHECK_CONTAINS(members(1)%text, want, 'items added before "/"')
        CHECK_CONTAINS(members(1)%text, 'rhoI2 = 2e-3, start(2) = 3.0 /', 'rod item added')
        call member_scene(members(1), member, ok)
        if (.not. ok) return
        CHECK_TRUE(all(member%loads(1)%force == [0.0_rk, -1.0_rk, -7.5_rk]), 'force')
        CHECK_TRUE(all(member%loads(1)%moment == [0.0_rk, 0.25_rk, 0.0_rk]), 'moment')
        CHECK_TRUE(member%loads(1)%t_on == 0.125_rk, 't_on')
        CHECK_TRUE(member%time%dt == 0.1_rk, 'dt')
        CHECK_TRUE(all(member%rods(1)%start == [0.0_rk, 3.0_rk, 0.0_rk]), 'start')
    end subroutine test_array_entries_and_items

    ! A single group the scene lacks is added at the end, once for all its sweeps.
    subroutine test_missing_single_group_added()
        character(len=:), allocatable :: want
        type(scene_t) :: scene, member
        type(sweep_member_t), allocatable :: members(:)
        logical :: ok
        call members_of(base // "&sweep parameter = 'solver%max_newton', values = 7, 9 /" // nl // &
            "&sweep parameter = 'solver%newton_atol', values = 1e-9, 1e-8, mode = 'zip' /", &
            scene, members, ok)
        if (.not. ok) return
        CHECK_EQUAL(size(members), 2, 'two members')
        want = nl // '&solver max_newton = 9, newton_atol = 1.0e-08 /' // nl
        CHECK_CONTAINS(members(2)%text, want, 'one &solver added')
        call member_scene(members(2), member, ok)
        if (.not. ok) return
        CHECK_EQUAL(member%solver%max_newton, 9, 'max_newton')
        CHECK_TRUE(member%solver%newton_atol == 1.0e-8_rk, 'newton_atol')
    end subroutine test_missing_single_group_added

    ! Integer variables are written as integers; a logspace of whole numbers rounds to them.
    subroutine test_integers_as_integers()
        type(scene_t) :: scene, member
        type(sweep_member_t), allocatable :: members(:)
        integer :: id
        logical :: ok
        call members_of(base // "&sweep parameter = 'rod(1)%n_elements', logspace = 2, 16, 4 /" // nl, &
            scene, members, ok)
        if (.not. ok) return
        CHECK_TRUE(scene%sweeps(1)%integral, 'integral set by the resolver')
        CHECK_TRUE(all(sweep_values(scene%sweeps(1)) == [2.0_rk, 4.0_rk, 8.0_rk, 16.0_rk]), 'whole')
        do id = 1, 4
            CHECK_TRUE(members(id)%values(1) == real(2**id, rk), 'member value whole')
            call member_scene(members(id), member, ok)
            if (ok) then
                CHECK_EQUAL(member%rods(1)%n_elements, 2**id, 'n_elements read back')
            end if
        end do
        CHECK_CONTAINS(members(3)%text, 'n_elements = 8,', 'written as an integer')
        CHECK_CONTAINS(members(3)%text, '! sweep member 3 of 4: rod(1)%n_elements = 8' // nl, 'comment')
    end subroutine test_integers_as_integers

    ! sweep_member builds member `id` alone, equal to the one of sweep_members; other ids fail.
    subroutine test_one_member_equals_all_members()
        type(scene_t) :: scene
        type(sweep_member_t), allocatable :: members(:)
        type(sweep_member_t) :: one
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        integer :: id
        logical :: ok
        text = base // "&sweep parameter = 'rod(1)%EI1', linspace = 1, 3, 3 /" // nl // &
            "&sweep parameter = 'load(1)%force(1)', values = 0.5, 0.75 /" // nl
        call members_of(text, scene, members, ok)
        if (.not. ok) return
        do id = 1, size(members)
            call sweep_member(text, 'sweep.nml', scene, id, one, errors)
            CHECK_EQUAL(one%id, id, 'id')
            CHECK_TRUE(one%text == members(id)%text, 'same text')
            CHECK_TRUE(all(one%values == members(id)%values), 'same values')
        end do
        CHECK_EQUAL(errors%count, 0, 'no errors')
        call sweep_member(text, 'sweep.nml', scene, 7, one, errors)
        CHECK_EQUAL(errors%count, 1, 'id beyond the members')
        CHECK_CONTAINS(errors%joined(), 'sweep.nml: &sweep: there is no sweep member 7 (members 1 to 6)', 'msg')
    end subroutine test_one_member_equals_all_members

    ! Paths: malformed, unknown group (with a suggestion), &sweep itself, a missing or needless
    ! group index, an unknown variable, a missing or needless element, a logical, twice.
    subroutine test_path_errors()
        character(len=:), allocatable :: want
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: joined
        call parse(base // &
            "&sweep parameter = 'rod(1).EI1', values = 1 /" // nl // &
            "&sweep parameter = 'rood(1)%EI1', values = 1 /" // nl // &
            "&sweep parameter = 'sweep(1)%values', values = 1 /" // nl // &
            "&sweep parameter = 'rod%EI1', values = 1 /" // nl // &
            "&sweep parameter = 'time(1)%dt', values = 1 /" // nl // &
            "&sweep parameter = 'rod(1)%EJ1', values = 1 /" // nl // &
            "&sweep parameter = 'load(1)%force', values = 1 /" // nl // &
            "&sweep parameter = 'rod(1)%EI1(2)', values = 1 /" // nl // &
            "&sweep parameter = 'time%quasistatic', values = 1 /" // nl // &
            "&sweep parameter = 'rod(1)%GJ', values = 1 /" // nl // &
            "&sweep parameter = ' ROD(1) % gj ', values = 2 /" // nl, scene, errors, 10)
        joined = errors%joined()
        CHECK_CONTAINS(joined, "sweep.nml:7: &sweep parameter: 'rod(1).EI1' is not a path into the scene", 'p')
        want = 'sweep.nml:8: &sweep parameter: unknown group "rood" in ''rood(1)%EI1''; ' // &
            'did you mean "rod"?; groups are run, time, solver, output, rod, bc, load, actuator, ' // &
            'joint, plate, contact'
        CHECK_CONTAINS(joined, want, 'g')
        CHECK_CONTAINS(joined, 'sweep.nml:9: &sweep parameter: a sweep cannot sweep a &sweep group', 's')
        want = "sweep.nml:10: &sweep parameter: &rod may appear several times: name " // &
            "which one in 'rod%EI1', e.g. rod(1)%EI1"
        CHECK_CONTAINS(joined, want, 'k')
        want = 'sweep.nml:11: &sweep parameter: &time appears at most once: write ' // &
            'time%dt without an index'
        CHECK_CONTAINS(joined, want, '1')
        want = 'sweep.nml:12: &sweep parameter: &rod has no variable "EJ1"; did you ' // &
            'mean "EI1"?'
        CHECK_CONTAINS(joined, want, 'v')
        want = 'sweep.nml:13: &sweep parameter: load(1)%force is an array of 3 values: ' // &
            'sweep one element, e.g. load(1)%force(1)'
        CHECK_CONTAINS(joined, want, 'a')
        want = 'sweep.nml:14: &sweep parameter: rod(1)%EI1 is a single value: write ' // &
            'it without the element index (2)'
        CHECK_CONTAINS(joined, want, 'e')
        want = 'sweep.nml:15: &sweep parameter: time%quasistatic is a logical ' // &
            'variable; only real and integer variables can be swept in this version'
        CHECK_CONTAINS(joined, want, 'l')
        want = 'sweep.nml:17: &sweep parameter: rod(1)%GJ is swept already by the ' // &
            '&sweep at line 16'
        CHECK_CONTAINS(joined, want, 't')
    end subroutine test_path_errors

    ! Values: none or two of values, linspace, logspace; a gap; a count that is not a whole
    ! number; logspace through 0; out of the variable's range; not whole for an integer; zip
    ! counts; too many members.
    subroutine test_value_errors()
        character(len=:), allocatable :: want
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: joined
        call parse(base // &
            "&sweep parameter = 'rod(1)%EI1' /" // nl // &
            "&sweep parameter = 'rod(1)%EI2', values = 1, linspace = 1, 2, 3 /" // nl // &
            "&sweep parameter = 'rod(1)%GJ', values(2) = 1 /" // nl // &
            "&sweep parameter = 'rod(1)%EA', linspace = 1, 2, 2.5 /" // nl // &
            "&sweep parameter = 'rod(1)%GA1', logspace = 0, 2, 3 /" // nl // &
            "&sweep parameter = 'rod(1)%GA2', values = 1, -1 /" // nl // &
            "&sweep parameter = 'rod(1)%n_elements', linspace = 1, 2, 3 /" // nl // &
            "&sweep parameter = 'rod(1)%rhoA', linspace(1) = 1 /" // nl, scene, errors, 8)
        joined = errors%joined()
        want = 'sweep.nml:7: &sweep values, linspace, logspace: give exactly one of ' // &
            'them (given: none)'
        CHECK_CONTAINS(joined, want, 'none')
        want = 'sweep.nml:8: &sweep values, linspace, logspace: give exactly one of ' // &
            'them (given: values, linspace)'
        CHECK_CONTAINS(joined, want, 'two')
        CHECK_CONTAINS(joined, 'sweep.nml:9: &sweep values: entry 1 is not given but a later one is', 'gap')
        want = 'sweep.nml:10: &sweep linspace: the count (third value) must be a whole ' // &
            'number from 2 to 4096 (given: 2.5)'
        CHECK_CONTAINS(joined, want, 'count')
        CHECK_CONTAINS(joined, 'sweep.nml:11: &sweep logspace: first and last must be > 0', 'log')
        want = 'sweep.nml:12: &sweep values: value 2, -1.0, is out of range for ' // &
            'rod(1)%GA2; allowed: > 0.0'
        CHECK_CONTAINS(joined, want, 'range')
        want = 'sweep.nml:13: &sweep linspace: rod(1)%n_elements is an integer ' // &
            'variable, but value 2, 1.5, is not a whole number'
        CHECK_CONTAINS(joined, want, 'integer')
        CHECK_CONTAINS(joined, 'sweep.nml:14: &sweep linspace: give all three of first, last, count', '3')

        call parse(base // "&sweep parameter = 'rod(1)%EI1', values = 1, 2 /" // nl // &
            "&sweep parameter = 'rod(1)%EI2', values = 1, 2, 3, mode = 'zip' /" // nl, scene, errors, 1)
        want = "sweep.nml:8: &sweep mode: 'zip' pairs the 3 value(s) of " // &
            'rod(1)%EI2 with the 2 value(s) of rod(1)%EI1 (the &sweep at line 7)'
        CHECK_CONTAINS(errors%joined(), want, 'zip')

        call parse(base // "&sweep parameter = 'rod(1)%EI1', logspace = 1, 2, 4096 /" // nl // &
            "&sweep parameter = 'rod(1)%EI2', logspace = 1, 2, 4096 /" // nl, scene, errors, 1)
        CHECK_CONTAINS(errors%joined(), 'sweep.nml: &sweep: the sweeps have more than ', 'limit')
        CHECK_TRUE(4096 * 4096 > max_sweep_members, 'the limit is below 4096^2')
    end subroutine test_value_errors

    ! Values that cannot be placed: an element past the given entries, an element of an array
    ! given element-wise, two elements of an array the group does not give.
    subroutine test_placement_errors()
        character(len=:), allocatable :: want
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: joined, text
        text = '&time t_end = 1, dt = 0.5 /' // nl // &
            "&rod n_elements = 2, length = 1, EA = 1, GA1 = 1, GA2 = 1, EI1 = 1, EI2 = 1, GJ = 1," // nl // &
            '     rhoA = 1, rhoI1 = 1, rhoI2 = 1, maxwell_fraction = 0.1, maxwell_tau_E = 1,' // nl // &
            '     start(2) = 1 /' // nl // &
            "&load rod = 'rod1', where = 'end' /" // nl
        call parse(text // "&sweep parameter = 'rod(1)%maxwell_fraction(3)', values = 0.2 /" // nl // &
            "&sweep parameter = 'rod(1)%start(1)', values = 2 /" // nl // &
            "&sweep parameter = 'load(1)%force(1)', values = 2 /" // nl // &
            "&sweep parameter = 'load(1)%force(2)', values = 2 /" // nl, scene, errors, 3)
        joined = errors%joined()
        want = 'sweep.nml:6: &sweep parameter: rod(1)%maxwell_fraction(3): the &rod at ' // &
            'line 2 gives 1 value(s) of maxwell_fraction; a sweep can set one of them or the next ' // &
            '(element 2)'
        CHECK_CONTAINS(joined, want, 'past')
        want = 'sweep.nml:7: &sweep parameter: rod(1)%start(1): the &rod at line 2 ' // &
            'assigns start(2) alone; to sweep rod(1)%start(1), give start there in full'
        CHECK_CONTAINS(joined, want, 'element-wise')
        want = 'sweep.nml:9: &sweep parameter: load(1)%force(2): another sweep sets an ' // &
            'element of force, which the &load at line 5 does not give'
        CHECK_CONTAINS(joined, want, 'two elements')

        ! The next entry past the given ones lengthens the list; element-wise given: replaced.
        call parse(text // "&sweep parameter = 'rod(1)%maxwell_fraction(2)', values = 0.2 /" // nl // &
            "&sweep parameter = 'rod(1)%maxwell_tau_E(2)', values = 3 /" // nl // &
            "&sweep parameter = 'rod(1)%start(2)', values = 2 /" // nl, scene, errors, 0)
        call check_sweep_members(text // "&sweep parameter = 'rod(1)%maxwell_fraction(2)', " // &
            'values = 0.2 /' // nl // "&sweep parameter = 'rod(1)%maxwell_tau_E(2)', values = 3 /" // &
            nl // "&sweep parameter = 'rod(1)%start(2)', values = 2 /" // nl, 'sweep.nml', scene, errors)
        CHECK_EQUAL(errors%count, 0, 'the member reads: ' // errors%joined())
    end subroutine test_placement_errors

    ! check_sweep_members: members whose scene is invalid (dt above t_end), prefixed with their
    ! id and values; at most 5 shown, then the count.
    subroutine test_failing_members_reported()
        character(len=:), allocatable :: want
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text, joined
        text = base // "&sweep parameter = 'time%dt', values = 0.5, 2, 3, 4, 5, 6, 7, 0.25 /" // nl // &
            "&sweep parameter = 'rod(1)%EI1', values = 1, 2 /" // nl
        call parse(text, scene, errors, 0)
        call check_sweep_members(text, 'sweep.nml', scene, errors)
        joined = errors%joined()
        CHECK_EQUAL(errors%count, 6, 'five members shown and the count: ' // joined)
        want = 'sweep member 3 (time%dt = 2.0, rod(1)%EI1 = 1.0): sweep.nml: &time dt: ' // &
            '2.0 is larger than t_end = 1.0'
        CHECK_CONTAINS(joined, want, 'first failing member')
        CHECK_CONTAINS(joined, 'sweep member 7 (time%dt = 4.0, rod(1)%EI1 = 1.0): ', 'fifth failing member')
        CHECK_TRUE(index(joined, 'sweep member 8 (') == 0, 'sixth failing member not shown')
        want = 'sweep.nml: &sweep: 12 of 16 sweep members are invalid (the first 5 ' // 'are shown)'
        CHECK_CONTAINS(joined, want, 'count')

        errors = error_list_t()
        text = base // "&sweep parameter = 'time%dt', values = 0.5, 0.25 /" // nl
        call parse(text, scene, errors, 0)
        call check_sweep_members(text, 'sweep.nml', scene, errors)
        CHECK_EQUAL(errors%count, 0, 'valid members: ' // errors%joined())
    end subroutine test_failing_members_reported

    ! A member's messages name the lines of the scene file: removed &sweep groups keep their
    ! line breaks, and the comment line is not part of what check_sweep_members reads.
    subroutine test_line_numbers_kept()
        character(len=:), allocatable :: want
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        ! A member error (an end driven by its velocity, which ph_director drives by its pose:
        ! check_capabilities; the base is not checked here) on line 9 of the file, the &sweep on
        ! lines 1-2.
        text = "&sweep parameter = 'rod(1)%EI2'," // nl // '  values = 1 /' // nl // base // &
            "&bc rod = 'beam', end = 'end', kind = 'driven', velocity = 1, 0, 0, time_function = 'ramp', t_off = 1 /" // nl
        call parse(text, scene, errors, 0)
        call check_sweep_members(text, 'sweep.nml', scene, errors)
        want = 'sweep member 1 (rod(1)%EI2 = 1.0): sweep.nml:9: &bc velocity'
        CHECK_CONTAINS(errors%joined(), want, 'line of the scene file')
    end subroutine test_line_numbers_kept

end module rs_test_io_sweep

!> Test program: runs the tests of rs_test_io_sweep; exits non-zero if any failed.
program test_sweep
    use rs_test_io_sweep, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_sweep
