#include "rs_assert.h"
!> Unit tests of rs_model_capabilities: ph_director's row of the capability matrix (DESIGN.md
!> §1, docs/user/capabilities.md) checked against every value the input language allows for
!> each column (src/io/input_spec.f90: bc kind, load where, load frame, rod constraint) and its
!> logical columns (quasistatic, viscoelastic, actuation, curved reference), the rows of
!> ph_planar and cl_em_planar (seed 001: pinned ends, revolute and rigid joints, planar), the
!> bundle columns (issue 10: ph_director has rigid, spherical and revolute joints, end plates
!> and contact; no other formulation has end plates or contact), the row of se3_strand (seed 004: other end
!> kinds at s = L than at s = 0, `end_kinds_at`, relaxation, ends driven by velocity against
!> se3_pg's by pose), the rows of unknown formulations, the list `formulation_names` (every
!> formulation the input language names has a row), and `lists_name`, which matches whole
!> '|'-separated names only.
module rs_test_model_capabilities
    use rs_test_assert, only: run_test, assert_true, assert_equal
    use rs_model_capabilities, only: capability_t, lists_name, end_kinds_at
    use rs_formulations_registry, only: capability_of, formulation_names
    implicit none
    private

    public :: run_all_tests

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('ph_director_row', test_ph_director_row)
        call run_test('ph_director_trailing_blanks', test_ph_director_trailing_blanks)
        call run_test('planar_rows', test_planar_rows)
        call run_test('unknown_formulations', test_unknown_formulations)
        call run_test('every_named_formulation_available', test_every_named_formulation_available)
        call run_test('se3_pg_row', test_se3_pg_row)
        call run_test('se3_strand_row', test_se3_strand_row)
        call run_test('end_kinds_at', test_end_kinds_at)
        call run_test('lists_name_whole_names', test_lists_name_whole_names)
        call run_test('lists_name_blank_and_empty', test_lists_name_blank_and_empty)
    end subroutine run_all_tests

    !> Check that exactly the names `supported` of the allowed input values `allowed` are in
    !> `list`.
    subroutine check_column(list, allowed, supported, column)
        character(len=*), intent(in) :: list, allowed(:), supported(:), column
        logical :: expected
        integer :: i
        do i = 1, size(allowed)
            expected = any(allowed(i) == supported)
            CHECK_EQUAL(lists_name(list, allowed(i)), expected, column // ': ' // trim(allowed(i)))
        end do
    end subroutine check_column

    ! seed 000 §2.9, §6.1: clamped and free ends; end, distributed and gravity loads, dead
    ! (spatial) only; with the extensions of seed 000 §5 (issue 4): the shear-rigid and
    ! inextensible constraints, quasistatics, Maxwell branches and actuators.
    subroutine test_ph_director_row()
        character(len=12), parameter :: kinds(7) = [character(len=12) :: 'clamped', 'pinned', 'free', &
            'driven', 'body', 'sliding', 'held']
        character(len=12), parameter :: places(4) = [character(len=12) :: 'start', 'end', &
            'distributed', 'gravity']
        character(len=12), parameter :: frames(2) = [character(len=12) :: 'spatial', 'follower']
        character(len=12), parameter :: constraints(3) = [character(len=12) :: 'none', 'kirchhoff', &
            'inextensible']
        character(len=12), parameter :: joints(3) = [character(len=12) :: 'revolute', 'rigid', &
            'spherical']
        character(len=12) :: supported_frames(2)
        type(capability_t) :: row
        row = capability_of('ph_director')
        CHECK_TRUE(row%available, 'ph_director is available')
        CHECK_EQUAL(trim(row%formulation), 'ph_director', 'row names its formulation')
        ! Issue 26 items 2, 3: pinned, driven, sliding and held ends; issue 24: bodies.
        call check_column(row%end_kinds, kinds, kinds, 'end kind')
        call check_column(row%load_places, places, places, 'load place')
        supported_frames(1) = 'spatial'
        ! Issue 26 item 2: follower loads.
        supported_frames(2) = 'follower'
        call check_column(row%load_frames, frames, supported_frames, 'load frame')
        call check_column(row%constraints, constraints, constraints, 'constraint')
        CHECK_TRUE(row%quasistatic, 'quasistatic runs')
        CHECK_TRUE(row%viscoelastic, 'Maxwell branches')
        CHECK_TRUE(row%actuation, 'pneumatic chambers and tendons')
        CHECK_TRUE(row%curved_reference, 'curved stress-free reference (helix, polyline)')
        call check_column(row%joints, joints, joints, 'joint')
        CHECK_TRUE(row%end_plates, 'end plates (issue 10)')
        CHECK_TRUE(row%contact, 'rod-rod and self contact (issue 10)')
        CHECK_TRUE(.not. row%planar, 'ph_director is 3D')
        CHECK_TRUE(.not. row%relaxation, 'statics by quasistatics, not relaxation')
        CHECK_EQUAL(trim(row%drive), 'pose', 'driven ends by their pose (issue 26 item 2)')
        CHECK_EQUAL(len_trim(row%end_kinds_at_end), 0, 'same end kinds at both ends')
    end subroutine test_ph_director_row

    ! seed 001 (methods/ph_planar.md): both planar formulations have clamped, pinned and free
    ! ends, dead end and distributed loads and gravity, no constraint, quasistatics, revolute
    ! and rigid joints; no Maxwell branches, actuators or curved reference.
    subroutine test_planar_rows()
        character(len=12), parameter :: kinds(4) = [character(len=12) :: 'clamped', 'pinned', 'free', &
            'driven']
        character(len=12), parameter :: places(4) = [character(len=12) :: 'start', 'end', &
            'distributed', 'gravity']
        character(len=12), parameter :: frames(2) = [character(len=12) :: 'spatial', 'follower']
        character(len=12), parameter :: constraints(3) = [character(len=12) :: 'none', 'kirchhoff', &
            'inextensible']
        character(len=12), parameter :: joints(3) = [character(len=12) :: 'revolute', 'rigid', &
            'spherical']
        character(len=12), parameter :: names(2) = [character(len=12) :: 'ph_planar', 'cl_em_planar']
        type(capability_t) :: row
        integer :: k
        do k = 1, size(names)
            row = capability_of(names(k))
            CHECK_TRUE(row%available, trim(names(k)) // ' is available')
            CHECK_EQUAL(trim(row%formulation), trim(names(k)), 'row names its formulation')
            call check_column(row%end_kinds, kinds, kinds(1:3), trim(names(k)) // ' end kind')
            CHECK_TRUE(lists_name(row%end_kinds, 'sliding'), trim(names(k)) // ' sliding ends')
            CHECK_TRUE(lists_name(row%end_kinds, 'held'), trim(names(k)) // ' held ends')
            call check_column(row%load_places, places, places, trim(names(k)) // ' load place')
            call check_column(row%load_frames, frames, frames(1:1), trim(names(k)) // ' load frame')
            call check_column(row%constraints, constraints, constraints(1:1), trim(names(k)) // &
                ' constraint')
            call check_column(row%joints, joints, joints(1:2), trim(names(k)) // ' joint')
            CHECK_TRUE(row%quasistatic, trim(names(k)) // ': quasistatic runs')
            CHECK_TRUE(.not. row%viscoelastic, trim(names(k)) // ': no Maxwell branches')
            CHECK_TRUE(.not. row%actuation, trim(names(k)) // ': no actuators')
            CHECK_TRUE(.not. row%curved_reference, trim(names(k)) // ': straight rods only')
            CHECK_TRUE(row%planar, trim(names(k)) // ' is planar')
            CHECK_TRUE(.not. row%end_plates, trim(names(k)) // ': no end plates')
            CHECK_TRUE(.not. row%contact, trim(names(k)) // ': no contact')
            CHECK_TRUE(.not. row%relaxation, trim(names(k)) // ': no relaxation')
            CHECK_EQUAL(len_trim(row%drive), 0, trim(names(k)) // ': no driven ends')
        end do
    end subroutine test_planar_rows

    ! Input strings are fixed-length and blank-padded.
    subroutine test_ph_director_trailing_blanks()
        character(len=64) :: name, kind
        type(capability_t) :: row
        name = 'ph_director'
        kind = 'free'
        row = capability_of(name)
        CHECK_TRUE(row%available, 'blank-padded name')
        CHECK_TRUE(lists_name(row%end_kinds, kind), 'blank-padded kind')
    end subroutine test_ph_director_trailing_blanks

    !> The row of `name` is unavailable and empty.
    subroutine check_unavailable(name)
        character(len=*), intent(in) :: name
        type(capability_t) :: row
        row = capability_of(name)
        CHECK_TRUE(.not. row%available, 'not available: "' // name // '"')
        CHECK_EQUAL(trim(row%formulation), trim(name), 'row names what was asked: "' // name // '"')
        CHECK_EQUAL(len_trim(row%end_kinds), 0, 'no end kinds: "' // name // '"')
        CHECK_EQUAL(len_trim(row%load_places), 0, 'no load places: "' // name // '"')
        CHECK_EQUAL(len_trim(row%load_frames), 0, 'no load frames: "' // name // '"')
        CHECK_EQUAL(len_trim(row%constraints), 0, 'no constraints: "' // name // '"')
        CHECK_TRUE(.not. row%quasistatic, 'not quasistatic: "' // name // '"')
        CHECK_TRUE(.not. row%viscoelastic, 'not viscoelastic: "' // name // '"')
        CHECK_TRUE(.not. row%actuation, 'no actuation: "' // name // '"')
        CHECK_TRUE(.not. row%curved_reference, 'no curved reference: "' // name // '"')
        CHECK_EQUAL(len_trim(row%joints), 0, 'no joints: "' // name // '"')
        CHECK_TRUE(.not. row%end_plates, 'no end plates: "' // name // '"')
        CHECK_TRUE(.not. row%contact, 'no contact: "' // name // '"')
        CHECK_TRUE(.not. row%planar, 'not planar: "' // name // '"')
        CHECK_TRUE(.not. row%relaxation, 'no relaxation: "' // name // '"')
        CHECK_EQUAL(len_trim(row%drive), 0, 'no drive: "' // name // '"')
        CHECK_EQUAL(len_trim(row%end_kinds_at_end), 0, 'no end kinds at s = L: "' // name // '"')
        CHECK_EQUAL(len(end_kinds_at(row, 'end')), 0, 'nothing at the end: "' // name // '"')
        CHECK_TRUE(.not. lists_name(row%end_kinds, 'clamped'), 'clamped not listed: "' // name // '"')
        CHECK_TRUE(.not. lists_name(row%constraints, 'none'), 'none not listed: "' // name // '"')
        CHECK_TRUE(.not. lists_name(row%constraints, ''), 'blank not listed: "' // name // '"')
    end subroutine check_unavailable

    subroutine test_unknown_formulations()
        call check_unavailable('ph_directr')
        call check_unavailable('PH_DIRECTOR')
        call check_unavailable('ph_director_x')
        call check_unavailable('ph')
        call check_unavailable('')
        call check_unavailable('auto')
    end subroutine test_unknown_formulations

    ! Every formulation of the list has an available row naming it; the list holds every
    ! formulation of DESIGN.md §1 once.
    subroutine test_every_named_formulation_available()
        type(capability_t) :: row
        character(len=32), allocatable :: names(:)
        integer :: i
        names = formulation_names()
        CHECK_EQUAL(size(names), 5, 'five formulations')
        do i = 1, size(names)
            row = capability_of(names(i))
            CHECK_TRUE(row%available, 'available: ' // trim(names(i)))
            CHECK_EQUAL(trim(row%formulation), trim(names(i)), 'row names it')
            CHECK_EQUAL(count(names == names(i)), 1, 'listed once')
        end do
        CHECK_TRUE(any(names == 'se3_strand'), 'se3_strand listed')
    end subroutine test_every_named_formulation_available

    ! seed 002 (issue 7): clamped and pinned ends, dead and follower end loads, distributed
    ! loads and gravity, statics, curved references; joints, end plates and contact through the
    ! system layer (issue 22 item 5); no constraints or planar limit.
    subroutine test_se3_pg_row()
        type(capability_t) :: row
        row = capability_of('se3_pg')
        CHECK_TRUE(row%available, 'se3_pg is available')
        CHECK_TRUE(lists_name(row%end_kinds, 'pinned'), 'pinned ends')
        CHECK_TRUE(lists_name(row%end_kinds, 'driven'), 'driven ends (a moved clamp)')
        CHECK_TRUE(lists_name(row%end_kinds, 'held'), 'held ends (issue 26 item 3)')
        CHECK_TRUE(lists_name(row%load_frames, 'follower'), 'follower loads')
        CHECK_TRUE(lists_name(row%load_places, 'gravity'), 'gravity')
        CHECK_TRUE(row%quasistatic .and. row%curved_reference, 'statics and curved references')
        CHECK_TRUE(.not. row%viscoelastic .and. .not. row%actuation .and. .not. row%planar, 'nothing more')
        CHECK_EQUAL(trim(row%joints), 'rigid|spherical|revolute', 'joints of every kind')
        CHECK_TRUE(row%end_plates .and. row%contact, 'end plates and contact')
        CHECK_EQUAL(trim(row%drive), 'pose', 'driven by displacement and rotation')
        CHECK_TRUE(.not. row%relaxation, 'statics by load increments, not relaxation')
        CHECK_EQUAL(len_trim(row%end_kinds_at_end), 0, 'same end kinds at both ends')
    end subroutine test_se3_pg_row

    ! seed 004 (methods/se3_strands.md §3.4): motion prescribed at s = 0 (clamped or driven by
    ! velocity) or a free start (issue 26 item 4), stress at s = L (free only); end and
    ! distributed loads, gravity, dead and follower; curved references; statics by relaxation,
    ! not quasistatics; damping, not Maxwell branches; no constraints, actuators, joints or
    ! planar limit.
    subroutine test_se3_strand_row()
        character(len=12), parameter :: kinds(4) = [character(len=12) :: 'clamped', 'pinned', 'free', &
            'driven']
        character(len=12), parameter :: places(4) = [character(len=12) :: 'start', 'end', &
            'distributed', 'gravity']
        character(len=12), parameter :: frames(2) = [character(len=12) :: 'spatial', 'follower']
        character(len=12), parameter :: constraints(3) = [character(len=12) :: 'none', 'kirchhoff', &
            'inextensible']
        character(len=12) :: at_start(3), at_end(1)
        type(capability_t) :: row
        row = capability_of('se3_strand')
        CHECK_TRUE(row%available, 'se3_strand is available')
        CHECK_EQUAL(trim(row%formulation), 'se3_strand', 'row names its formulation')
        at_start = [character(len=12) :: 'clamped', 'driven', 'free']
        at_end = [character(len=12) :: 'free']
        call check_column(row%end_kinds, kinds, at_start, 'end kind at s = 0')
        call check_column(row%end_kinds_at_end, kinds, at_end, 'end kind at s = L')
        call check_column(end_kinds_at(row, 'start'), kinds, at_start, 'end_kinds_at start')
        call check_column(end_kinds_at(row, 'end'), kinds, at_end, 'end_kinds_at end')
        call check_column(row%load_places, places, places(2:4), 'load place')
        call check_column(row%load_frames, frames, frames, 'load frame')
        call check_column(row%constraints, constraints, constraints(1:1), 'constraint')
        CHECK_TRUE(.not. row%quasistatic, 'no quasistatics')
        CHECK_TRUE(row%relaxation, 'statics by damped dynamics')
        CHECK_EQUAL(trim(row%drive), 'velocity', 'driven by velocity (P0 = M V0)')
        CHECK_TRUE(.not. row%viscoelastic, 'no Maxwell branches')
        CHECK_TRUE(row%damping, 'Kelvin-Voigt and drag')
        CHECK_TRUE(.not. row%actuation, 'no actuators')
        CHECK_TRUE(row%curved_reference, 'curved relaxed shapes')
        CHECK_EQUAL(len_trim(row%joints), 0, 'no joints')
        CHECK_TRUE(.not. row%end_plates .and. .not. row%contact, 'no end plates or contact')
        CHECK_TRUE(.not. row%planar, 'se3_strand is 3D')
    end subroutine test_se3_strand_row

    ! A blank end_kinds_at_end means the same kinds at both ends; a given one holds at 'end'
    ! only; a blank or unknown end name takes end_kinds.
    subroutine test_end_kinds_at()
        type(capability_t) :: row
        character(len=64) :: padded
        row%end_kinds = 'clamped|free'
        CHECK_EQUAL(end_kinds_at(row, 'start'), 'clamped|free', 'start')
        CHECK_EQUAL(end_kinds_at(row, 'end'), 'clamped|free', 'end, blank end_kinds_at_end')
        row%end_kinds_at_end = 'free'
        CHECK_EQUAL(end_kinds_at(row, 'start'), 'clamped|free', 'start keeps end_kinds')
        CHECK_EQUAL(end_kinds_at(row, 'end'), 'free', 'end takes end_kinds_at_end')
        padded = 'end'
        CHECK_EQUAL(end_kinds_at(row, padded), 'free', 'blank-padded end name')
        CHECK_EQUAL(end_kinds_at(row, ''), 'clamped|free', 'blank end name')
    end subroutine test_end_kinds_at

    subroutine test_lists_name_whole_names()
        CHECK_TRUE(lists_name('clamped|free', 'free'), 'last name')
        CHECK_TRUE(lists_name('clamped|free', 'clamped'), 'first name')
        CHECK_TRUE(lists_name('start|end|distributed|gravity', 'end'), 'inner name')
        CHECK_TRUE(lists_name('none', 'none'), 'single name')
        CHECK_TRUE(.not. lists_name('clamped|free', 'fre'), 'prefix of a name')
        CHECK_TRUE(.not. lists_name('clamped|free', 'ree'), 'suffix of a name')
        CHECK_TRUE(.not. lists_name('clamped|free', 'lamped'), 'suffix of the first name')
        CHECK_TRUE(.not. lists_name('clamped|free', 'clamped|'), 'name with a bar')
        CHECK_TRUE(.not. lists_name('clamped|free', 'd|f'), 'across the bar')
        CHECK_TRUE(.not. lists_name('clamped|free', 'clamped|free'), 'the whole list is not a name')
        CHECK_TRUE(.not. lists_name('start|end|distributed|gravity', 'distribute'), 'prefix inside')
        CHECK_TRUE(.not. lists_name('none', 'nonee'), 'longer name')
        CHECK_TRUE(.not. lists_name('clamped|free', 'Free'), 'case matters')
    end subroutine test_lists_name_whole_names

    subroutine test_lists_name_blank_and_empty()
        CHECK_TRUE(.not. lists_name('clamped|free', ''), 'empty name')
        CHECK_TRUE(.not. lists_name('clamped|free', '   '), 'blank name')
        CHECK_TRUE(.not. lists_name('', 'free'), 'empty list')
        CHECK_TRUE(.not. lists_name('', ''), 'empty name in an empty list')
        CHECK_TRUE(.not. lists_name('    ', ''), 'empty name in a blank list')
        CHECK_TRUE(lists_name('clamped|free      ', 'free'), 'blank-padded list')
        CHECK_TRUE(lists_name('clamped|free', 'free    '), 'blank-padded name')
    end subroutine test_lists_name_blank_and_empty

end module rs_test_model_capabilities

!> Test program: runs the tests of rs_test_model_capabilities; exits non-zero if any failed.
program test_capabilities
    use rs_test_model_capabilities, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_capabilities
