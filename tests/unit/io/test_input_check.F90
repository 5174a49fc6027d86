#include "rs_assert.h"
!> Unit tests of rs_io_input_check for the ph_director extensions (issue 4): Maxwell branches of
!> &rod (the number of branches, maxwell_tau_G defaulted per branch to maxwell_tau_E, the rules
!> on gaps, counts and the sum of fractions), the cross-checks of &actuator (rod, kind-specific
!> variables, offset inside a circle or tube section, time function), and the capability checks
!> of a rod against a capability row built in the test, so that rows without constraints,
!> quasistatics, Maxwell branches or actuation can be exercised although ph_director has them
!> all; and the reference geometry (helix and polyline lengths, start, direction and default d1
!> derived, their errors), the curved-reference capability and the initial-velocity checks.
!> 'auto' per system of joined rods (formulation, origin and reason), em_variant's default and
!> the joint checks of one scene reported together. Each error is checked for its file, line,
!> group and variable.
module rs_test_io_input_check
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_list_t
    use rs_test_assert, only: run_test, assert_true, assert_equal, assert_contains, assert_close
    use rs_model_scene, only: scene_t, unset_real, max_branches
    use rs_model_capabilities, only: capability_t, capability_of
    use rs_io_input_file, only: parse_scene
    use rs_io_input_check, only: check_capabilities, check_rod_capabilities
    implicit none
    private

    public :: run_all_tests

    character(len=*), parameter :: nl = new_line('a')

    !> Rod stiffnesses given directly (section = 'none').
    character(len=*), parameter :: direct = 'EA = 1e4, GA1 = 2e3, GA2 = 3e3, EI1 = 12.5, ' // &
        'EI2 = 13.5, GJ = 7, rhoA = 0.5, rhoI1 = 1e-3, rhoI2 = 2e-3'
    character(len=*), parameter :: time = '&time t_end = 1, dt = 0.5 /' // nl
    !> A valid rod 'arm' (line 2 after `time`) and the start of a valid tendon on it.
    character(len=*), parameter :: arm = "&rod name = 'arm', n_elements = 2, length = 1, " // &
        direct // ' /' // nl
    character(len=*), parameter :: tendon = "&actuator rod = 'arm', kind = 'tendon', " // &
        'offset = 0, 0, tension = 1'
    !> The start of a rod named `x`, continued by the test.
    character(len=*), parameter :: rod_x = "&rod n_elements = 2, length = 1, name = '"

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('maxwell_branches_and_tau_G_default', test_maxwell_branches_and_tau_G_default)
        call run_test('maxwell_errors', test_maxwell_errors)
        call run_test('maxwell_gaps', test_maxwell_gaps)
        call run_test('actuator_values_and_defaults', test_actuator_values_and_defaults)
        call run_test('actuator_errors', test_actuator_errors)
        call run_test('actuator_offset_inside_section', test_actuator_offset_inside_section)
        call run_test('actuator_time_function_errors', test_actuator_time_function_errors)
        call run_test('constraint_keeps_stiffnesses', test_constraint_keeps_stiffnesses)
        call run_test('ph_director_accepts_extensions', test_ph_director_accepts_extensions)
        call run_test('row_without_extensions', test_row_without_extensions)
        call run_test('helix_resolution', test_helix_resolution)
        call run_test('polyline_resolution', test_polyline_resolution)
        call run_test('curved_reference_capability', test_curved_reference_capability)
        call run_test('initial_velocity_checks', test_initial_velocity_checks)
        call run_test('auto_per_system', test_auto_per_system)
        call run_test('joint_errors_collected', test_joint_errors_collected)
    end subroutine run_all_tests

    !> Parse `text` as file 'c.nml' and check that it has exactly `n_errors` errors.
    subroutine parse(text, scene, errors, n_errors)
        character(len=*), intent(in) :: text
        type(scene_t), intent(out) :: scene
        type(error_list_t), intent(out) :: errors
        integer, intent(in) :: n_errors
        call parse_scene(text, 'c.nml', scene, errors)
        CHECK_EQUAL(errors%count, n_errors, 'number of errors; errors: ' // errors%joined())
    end subroutine parse

    ! Two branches with tau_G given for the second only: tau_G(1) = tau_E(1); three branches
    ! without tau_G: tau_G = tau_E; a rod without branches keeps every entry unset.
    subroutine test_maxwell_branches_and_tau_G_default()
        real(rk), parameter :: fractions(2) = [0.3_rk, 0.2_rk], tau_E(2) = [0.5_rk, 4.0_rk]
        real(rk), parameter :: tau_G(2) = [0.5_rk, 6.0_rk], quarters(3) = 0.25_rk
        real(rk), parameter :: tau_3(3) = [1.0_rk, 2.0_rk, 3.0_rk]
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        text = time // &
            '&rod n_elements = 2, length = 1, ' // direct // ',' // nl // &
            '     maxwell_fraction = 0.3, 0.2, maxwell_tau_E = 0.5, 4,' // nl // &
            '     maxwell_tau_G(2) = 6 /' // nl // &
            '&rod n_elements = 2, length = 1, ' // direct // ',' // nl // &
            '     maxwell_fraction = 3*0.25, maxwell_tau_E = 1, 2, 3 /' // nl // &
            '&rod n_elements = 2, length = 1, ' // direct // ' /' // nl
        call parse(text, scene, errors, 0)
        if (size(scene%rods) /= 3) return
        associate (rod => scene%rods(1))
            CHECK_CLOSE(rod%maxwell_fraction(1:2), fractions, 0.0_rk, 0.0_rk, 'fractions')
            CHECK_CLOSE(rod%maxwell_tau_E(1:2), tau_E, 0.0_rk, 0.0_rk, 'tau_E')
            CHECK_CLOSE(rod%maxwell_tau_G(1:2), tau_G, 0.0_rk, 0.0_rk, 'tau_G(1) = tau_E(1)')
            CHECK_TRUE(all(rod%maxwell_fraction(3:) == unset_real), 'two branches only')
            CHECK_TRUE(all(rod%maxwell_tau_G(3:) == unset_real), 'no tau_G beyond the branches')
        end associate
        associate (rod => scene%rods(2))
            CHECK_CLOSE(rod%maxwell_fraction(1:3), quarters, 0.0_rk, 0.0_rk, '3*0.25')
            CHECK_CLOSE(rod%maxwell_tau_G(1:3), tau_3, 0.0_rk, 0.0_rk, 'tau_G = tau_E')
        end associate
        CHECK_EQUAL(size(scene%rods(3)%maxwell_tau_G), max_branches, 'capacity')
        CHECK_TRUE(all(scene%rods(3)%maxwell_fraction == unset_real), 'elastic rod: no branches')
        CHECK_TRUE(all(scene%rods(3)%maxwell_tau_G == unset_real), 'elastic rod: no tau_G')
    end subroutine test_maxwell_branches_and_tau_G_default

    ! The fractions must leave the elastic branch a positive share; one tau_E per branch;
    ! no tau_G beyond the branches; the range of each entry is the reader's.
    subroutine test_maxwell_errors()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: fragment
        character(len=:), allocatable :: text, joined
        text = time // &                                                                         ! 1
            rod_x // "a', " // direct // ',' // nl // &   ! 2
            '     maxwell_fraction = 0.5, 0.5, maxwell_tau_E = 1, 1 /' // nl // &
            rod_x // "b', " // direct // ',' // nl // &   ! 4
            '     maxwell_fraction = 0.5, 0.25, maxwell_tau_E = 1 /' // nl // &
            rod_x // "c', " // direct // ',' // nl // &   ! 6
            '     maxwell_tau_E = 1 /' // nl // &
            rod_x // "d', " // direct // ',' // nl // &   ! 8
            '     maxwell_fraction = 0.1, maxwell_tau_E = 1, maxwell_tau_G = 1, 2 /' // nl
        call parse(text, scene, errors, 4)
        joined = errors%joined()
        fragment = "c.nml:2: &rod 'a' maxwell_fraction: the fractions sum to 1.0; the sum" &
            // " must be < 1"
        CHECK_CONTAINS(joined, fragment, 'sum')
        fragment = "c.nml:4: &rod 'b' maxwell_tau_E: one relaxation time per Maxwell" &
            // " branch; 2 maxwell_fraction and 1 maxwell_tau_E given"
        CHECK_CONTAINS(joined, fragment, 'count')
        fragment = "c.nml:6: &rod 'c' maxwell_tau_E: one relaxation time per Maxwell" &
            // " branch; 0 maxwell_fraction and 1"
        CHECK_CONTAINS(joined, fragment, 'no branches')
        fragment = "c.nml:8: &rod 'd' maxwell_tau_G: given for branch 2, but there are 1" &
            // " branches"
        CHECK_CONTAINS(joined, fragment, 'tau_G')
        text = time // '&rod n_elements = 2, length = 1, ' // direct // ',' // nl // &
            '     maxwell_fraction = 1.0, maxwell_tau_E = 0 /' // nl
        call parse(text, scene, errors, 2)
        fragment = 'c.nml:3: &rod maxwell_fraction: value 1.0 out of range; allowed: >' &
            // ' 0.0 and < 1.0'
        CHECK_CONTAINS(errors%joined(), fragment, 'fraction range')
        fragment = 'c.nml:3: &rod maxwell_tau_E: value 0 out of range; allowed: > 0.0'
        CHECK_CONTAINS(errors%joined(), fragment, 'tau range')
    end subroutine test_maxwell_errors

    ! Branches are numbered from 1 without gaps (subscripted entries).
    subroutine test_maxwell_gaps()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: fragment
        character(len=:), allocatable :: text
        text = time // &
            rod_x // "a', " // direct // ',' // nl // &   ! 2
            '     maxwell_fraction(2) = 0.5, maxwell_tau_E(2) = 1 /' // nl // &
            rod_x // "b', " // direct // ',' // nl // &   ! 4
            '     maxwell_fraction = 0.5, maxwell_tau_E(3) = 1 /' // nl
        call parse(text, scene, errors, 3)
        fragment = "c.nml:2: &rod 'a' maxwell_fraction: entry 1 is not given but a later" &
            // " one is"
        CHECK_CONTAINS(errors%joined(), fragment, 'gap a')
        fragment = "c.nml:2: &rod 'a' maxwell_tau_E: entry 1 is not given"
        CHECK_CONTAINS(errors%joined(), fragment, 'gap a tau')
        fragment = "c.nml:4: &rod 'b' maxwell_tau_E: entry 1 is not given"
        CHECK_CONTAINS(errors%joined(), fragment, 'gap b')
    end subroutine test_maxwell_gaps

    ! Values land in their fields; kind folded; the time function defaults of &load.
    subroutine test_actuator_values_and_defaults()
        real(rk), parameter :: offset(2) = [0.01_rk, -0.02_rk]
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        text = time // arm // &
            "&actuator rod = 'arm', kind = 'Pneumatic', offset = 0.01, -0.02," // nl // &
            '          area = 2e-5,' // nl // &
            '          pressure = 3e4 /' // nl // &
            "&actuator rod = 'arm', kind = 'tendon', offset = 0, 0.005, tension = 12.5," // nl // &
            "          time_function = 'ramp', t_on = 0.25, t_off = 0.75 /" // nl
        call parse(text, scene, errors, 0)
        CHECK_EQUAL(size(scene%actuators), 2, 'two actuators')
        if (size(scene%actuators) /= 2) return
        associate (a => scene%actuators(1))
            CHECK_EQUAL(a%input_line, 3, 'line of the first actuator')
            CHECK_EQUAL(trim(a%rod), 'arm', 'rod')
            CHECK_EQUAL(trim(a%kind), 'pneumatic', 'kind folded to lower case')
            CHECK_CLOSE(a%offset, offset, 0.0_rk, 0.0_rk, 'offset')
            CHECK_CLOSE(a%area, 2.0e-5_rk, 0.0_rk, 0.0_rk, 'area')
            CHECK_CLOSE(a%pressure, 3.0e4_rk, 0.0_rk, 0.0_rk, 'pressure')
            CHECK_TRUE(a%tension == unset_real, 'no tension')
            CHECK_EQUAL(trim(a%time_function), 'constant', 'default time function')
            CHECK_CLOSE(a%t_on, 0.0_rk, 0.0_rk, 0.0_rk, 'default t_on')
            CHECK_TRUE(a%t_off == unset_real, 't_off unset')
            CHECK_TRUE(all(a%table_times == unset_real), 'no table')
        end associate
        associate (a => scene%actuators(2))
            CHECK_EQUAL(a%input_line, 6, 'line of the second actuator')
            CHECK_CLOSE(a%tension, 12.5_rk, 0.0_rk, 0.0_rk, 'tension')
            CHECK_TRUE(a%area == unset_real .and. a%pressure == unset_real, 'no area, no pressure')
            CHECK_EQUAL(trim(a%time_function), 'ramp', 'time function')
            CHECK_CLOSE(a%t_on, 0.25_rk, 0.0_rk, 0.0_rk, 't_on')
            CHECK_CLOSE(a%t_off, 0.75_rk, 0.0_rk, 0.0_rk, 't_off')
        end associate
    end subroutine test_actuator_values_and_defaults

    subroutine test_actuator_errors()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: fragment
        character(len=:), allocatable :: text, joined
        text = time // arm // &                                                           ! 2
            "&actuator rod = 'leg', kind = 'tendon', offset = 0, 0, tension = 1 /" // nl // & ! 3
            "&actuator rod = 'arm', kind = 'pneumatic', offset = 0, 0 /" // nl // &           ! 4
            "&actuator rod = 'arm', kind = 'tendon', offset = 0, 0, area = 1," // &
            ' pressure = 2 /' // nl // &                                                      ! 5
            "&actuator rod = 'arm', kind = 'pneumatic', offset = 0, 0, area = 1," // &
            ' pressure = 2, tension = 3 /' // nl // &                                         ! 6
            "&actuator rod = 'arm', kind = 'tendon', offset(2) = 0.001, tension = 1 /" // nl  ! 7
        call parse(text, scene, errors, 8)
        joined = errors%joined()
        fragment = "c.nml:3: &actuator rod: no rod is named 'leg'; rods: 'arm'"
        CHECK_CONTAINS(joined, fragment, 'unknown rod')
        CHECK_CONTAINS(joined, "c.nml:4: &actuator area: required for kind = 'pneumatic'", 'area')
        fragment = "c.nml:4: &actuator pressure: required for kind = 'pneumatic'"
        CHECK_CONTAINS(joined, fragment, 'pressure')
        fragment = "c.nml:5: &actuator tension: required for kind = 'tendon'"
        CHECK_CONTAINS(joined, fragment, 'tension')
        fragment = "c.nml:5: &actuator area: not allowed for kind = 'tendon'"
        CHECK_CONTAINS(joined, fragment, 'area for a tendon')
        fragment = "c.nml:5: &actuator pressure: not allowed for kind = 'tendon'"
        CHECK_CONTAINS(joined, fragment, 'pressure for a tendon')
        fragment = "c.nml:6: &actuator tension: not allowed for kind = 'pneumatic'"
        CHECK_CONTAINS(joined, fragment, 'tension for a chamber')
        fragment = 'c.nml:7: &actuator offset: both material coordinates'
        CHECK_CONTAINS(joined, fragment, 'half an offset')
        ! Reader errors stop the cross-checks (they would repeat them): a scene apart.
        text = time // arm // "&actuator rod = 'arm', kind = 'pneumatik', tension = -1 /" // nl
        call parse(text, scene, errors, 3)
        joined = errors%joined()
        fragment = "c.nml:3: &actuator kind: ""pneumatik"" is not allowed; allowed:" &
            // " 'pneumatic', 'tendon'"
        CHECK_CONTAINS(joined, fragment, 'kind')
        fragment = 'c.nml:3: &actuator tension: value -1 out of range; allowed: >= 0.0'
        CHECK_CONTAINS(joined, fragment, 'tendons pull')
        CHECK_CONTAINS(joined, 'c.nml:3: &actuator offset: required but not given', 'offset')
    end subroutine test_actuator_errors

    ! |offset| <= radius for a circle and a tube (outer radius); no check for a rectangle or
    ! stiffnesses given directly.
    subroutine test_actuator_offset_inside_section()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: fragment
        character(len=:), allocatable :: text, material
        material = ', E = 6e5, G = 2e5, density = 1080 /'
        text = time // &
            rod_x // "c', section = 'circle', radius = 0.015" // material // nl // &
            "&rod name = 't', n_elements = 2, length = 1, section = 'tube', radius = 0.02," // &
            ' inner_radius = 0.01' // material // nl // &
            "&rod name = 'r', n_elements = 2, length = 1, section = 'rectangle', width = 0.01," // &
            " height = 0.01, torsion_constant = 'polar'" // material // nl // &
            "&rod name = 'd', n_elements = 2, length = 1, " // direct // ' /' // nl // &
            "&actuator rod = 'c', kind = 'tendon', offset = 0, 0.015, tension = 1 /" // nl // & ! 6: rim
            "&actuator rod = 'c', kind = 'tendon', offset = 0.065, 0, tension = 1 /" // nl // & ! 7: out
            "&actuator rod = 't', kind = 'pneumatic', offset = 0, -0.021, area = 1e-5," // &
            ' pressure = 1 /' // nl // &                                                     ! 8: out
            "&actuator rod = 't', kind = 'pneumatic', offset = 0, -0.005, area = 1e-5," // &
            ' pressure = 1 /' // nl // &                                                     ! 9: bore
            "&actuator rod = 'r', kind = 'tendon', offset = 1, 1, tension = 1 /" // nl // &     ! 10
            "&actuator rod = 'd', kind = 'tendon', offset = 1, 1, tension = 1 /" // nl          ! 11
        call parse(text, scene, errors, 2)
        fragment = "c.nml:7: &actuator offset: |offset| = 0.065 lies outside the circle" &
            // " section of rod 'c' (radius 0.015)"
        CHECK_CONTAINS(errors%joined(), fragment, 'circle')
        fragment = "c.nml:8: &actuator offset: |offset| = 0.021 lies outside the tube" &
            // " section of rod 't' (radius 0.02)"
        CHECK_CONTAINS(errors%joined(), fragment, 'tube')
    end subroutine test_actuator_offset_inside_section

    ! The time-function rules of &load hold for &actuator.
    subroutine test_actuator_time_function_errors()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: fragment
        character(len=:), allocatable :: text
        text = time // arm // &
            tendon // ", time_function = 'hat' /" // nl // &
            tendon // ", time_function = 'pulse', t_on = 0.5, t_off = 0.25 /" // nl // &
            tendon // ", time_function = 'table', table_times = 0, 1, 1," // &
            ' table_values = 0, 1, 2 /' // nl // &
            tendon // ", time_function = 'table', table_times = 0, 1, 2, table_values = 0, 1 /" // nl
        call parse(text, scene, errors, 4)
        fragment = "c.nml:3: &actuator t_off: required by time_function = 'hat'"
        CHECK_CONTAINS(errors%joined(), fragment, 'hat')
        fragment = 'c.nml:4: &actuator t_off: 0.25 must be larger than t_on = 0.5'
        CHECK_CONTAINS(errors%joined(), fragment, 'pulse')
        fragment = 'c.nml:5: &actuator table_times: must be strictly increasing'
        CHECK_CONTAINS(errors%joined(), fragment, 'table')
        fragment = 'c.nml:6: &actuator table_times: a table needs at least 2 times and as' &
            // ' many table_values (3 and 2 given)'
        CHECK_CONTAINS(errors%joined(), fragment, 'counts')
    end subroutine test_actuator_time_function_errors

    ! A constrained rod may give (or derive from a section) the stiffnesses its constraint
    ! ignores: no error, and the values are kept.
    subroutine test_constraint_keeps_stiffnesses()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        text = time // "&rod n_elements = 2, length = 1, constraint = 'inextensible', " // &
            direct // ' /' // nl // &
            "&rod n_elements = 2, length = 1, constraint = 'kirchhoff', section = 'circle'," // &
            ' radius = 0.01, E = 1e9, nu = 0.5, density = 1000 /' // nl
        call parse(text, scene, errors, 0)
        if (size(scene%rods) /= 2) return
        CHECK_CLOSE(scene%rods(1)%EA, 1.0e4_rk, 0.0_rk, 0.0_rk, 'given EA kept')
        CHECK_CLOSE(scene%rods(1)%GA1, 2.0e3_rk, 0.0_rk, 0.0_rk, 'given GA1 kept')
        CHECK_TRUE(scene%rods(2)%GA1 /= unset_real, 'derived from the section')
        call check_capabilities(scene, errors)
        CHECK_EQUAL(errors%count, 0, 'ph_director takes both constraints: ' // errors%joined())
    end subroutine test_constraint_keeps_stiffnesses

    !> A scene with every extension on one ph_director rod.
    function extended_scene() result(text)
        character(len=:), allocatable :: text
        text = '&time t_end = 1, dt = 0.5, quasistatic = .true. /' // nl // &               ! 1
            rod_x // "arm', constraint = 'kirchhoff'," // nl // &                           ! 2
            '     maxwell_fraction = 0.2, maxwell_tau_E = 1, ' // direct // ' /' // nl // &
            "&rod name = 'plain', n_elements = 2, length = 1, " // direct // ' /' // nl // &     ! 4
            "&actuator rod = 'arm', kind = 'tendon', offset = 0, 0.01, tension = 2 /" // nl      ! 5
    end function extended_scene

    subroutine test_ph_director_accepts_extensions()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        call parse(extended_scene(), scene, errors, 0)
        call check_capabilities(scene, errors)
        CHECK_EQUAL(errors%count, 0, 'ph_director has every extension: ' // errors%joined())
    end subroutine test_ph_director_accepts_extensions

    ! A row with nothing of issue 4 rejects each extension with file, line, group, variable;
    ! a rod that asks for none of them passes the same row.
    subroutine test_row_without_extensions()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: fragment
        type(capability_t) :: row
        character(len=:), allocatable :: joined
        call parse(extended_scene(), scene, errors, 0)
        row = capability_of('ph_director')
        row%formulation = 'basic'
        row%constraints = 'none'
        row%quasistatic = .false.
        row%viscoelastic = .false.
        row%actuation = .false.
        call check_rod_capabilities(scene, 1, row, errors)
        CHECK_EQUAL(errors%count, 4, 'four extensions rejected: ' // errors%joined())
        joined = errors%joined()
        fragment = "c.nml:2: &rod constraint: 'kirchhoff' is not available for" &
            // " formulation 'basic'; available: none (docs/user/capabilities.md)"
        CHECK_CONTAINS(joined, fragment, 'constraint')
        fragment = "c.nml:2: &rod maxwell_fraction: Maxwell branches (viscoelasticity)" &
            // " are not available for formulation 'basic' (rod 'arm')" &
            // " (docs/user/capabilities.md)"
        CHECK_CONTAINS(joined, fragment, 'maxwell')
        fragment = "c.nml: &time quasistatic: not available for formulation 'basic' (rod" &
            // " 'arm')"
        CHECK_CONTAINS(joined, fragment, 'quasistatic')
        fragment = "c.nml:5: &actuator kind: 'tendon' actuators (actuation) are not" &
            // " available for formulation 'basic' (rod 'arm')"
        CHECK_CONTAINS(joined, fragment, 'actuation')
        errors = error_list_t()
        scene%time%quasistatic = .false.
        call check_rod_capabilities(scene, 2, row, errors)
        CHECK_EQUAL(errors%count, 0, 'a plain rod passes: ' // errors%joined())
    end subroutine test_row_without_extensions

    ! A helix: length, direction, default d1 (normal to the tangent at s = 0) and the centre of
    ! rotation derived; a given length that agrees is kept, one that does not is an error.
    subroutine test_helix_resolution()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        real(rk) :: length, t(3), expected(3)
        character(len=:), allocatable :: fragment
        call parse(time // "&rod n_elements = 4, geometry = 'helix', direction = 0, 0, 2," // &
            ' start = 1, 2, 3, helix_radius = 0.5, helix_pitch = 0.1, helix_turns = 2, ' // direct // &
            ' /' // nl, scene, errors, 0)
        length = 2.0_rk * sqrt((2.0_rk * acos(-1.0_rk) * 0.5_rk)**2 + 0.01_rk)
        CHECK_CLOSE(scene%rods(1)%length, length, 0.0_rk, 1.0e-15_rk, 'derived length')
        expected = [0.0_rk, 0.0_rk, 1.0_rk]
        CHECK_CLOSE(scene%rods(1)%direction, expected, 0.0_rk, 0.0_rk, 'axis normalized')
        ! u = e_x (axis e_z), w = e_y: t(0) = (0, R, b) / c, default d1 = e_z x t(0) normalized.
        t = [0.0_rk, 0.5_rk, 0.1_rk / (2.0_rk * acos(-1.0_rk))]
        t = t / norm2(t)
        expected = [-1.0_rk, 0.0_rk, 0.0_rk]
        CHECK_CLOSE(scene%rods(1)%d1, expected, 1.0e-15_rk, 0.0_rk, 'default d1 normal to t(0)')
        CHECK_CLOSE(dot_product(scene%rods(1)%d1, t), 0.0_rk, 1.0e-15_rk, 0.0_rk, 'd1 . t(0) = 0')
        expected = [1.0_rk, 2.0_rk, 3.0_rk]
        CHECK_CLOSE(scene%rods(1)%rotation_center, expected, 0.0_rk, 0.0_rk, 'rotation_center = start')
        call parse(time // "&rod n_elements = 4, geometry = 'helix', helix_radius = 0.5," // &
            ' helix_pitch = 0.1, helix_turns = 2, length = 6.2863676, ' // direct // ' /' // nl, &
            scene, errors, 0)
        CHECK_CLOSE(scene%rods(1)%length, length, 0.0_rk, 1.0e-15_rk, 'agreeing length replaced')
        call parse(time // "&rod n_elements = 4, geometry = 'helix', helix_radius = 0.5," // &
            ' helix_pitch = 0.1, helix_turns = 2, length = 6.3, ' // direct // ' /' // nl, &
            scene, errors, 1)
        fragment = "c.nml:2: &rod 'rod1' length: 6.3 given, but the helix is 6.286367600161276 long"
        CHECK_CONTAINS(errors%joined(), fragment, 'length contradicts the helix')
    end subroutine test_helix_resolution

    ! A polyline: start, direction and length from its points; errors for points that do not
    ! make one.
    subroutine test_polyline_resolution()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        real(rk) :: expected(3)
        character(len=:), allocatable :: joined
        call parse(time // "&rod n_elements = 4, geometry = 'polyline'," // &
            ' points = 1, 1, 1, 4, 5, 1, 4, 5, 3, ' // direct // ' /' // nl, scene, errors, 0)
        expected = [1.0_rk, 1.0_rk, 1.0_rk]
        CHECK_CLOSE(scene%rods(1)%start, expected, 0.0_rk, 0.0_rk, 'start = first point')
        expected = [0.6_rk, 0.8_rk, 0.0_rk]
        CHECK_CLOSE(scene%rods(1)%direction, expected, 1.0e-16_rk, 0.0_rk, 'first segment direction')
        CHECK_CLOSE(scene%rods(1)%length, 7.0_rk, 0.0_rk, 0.0_rk, 'length 5 + 2')
        expected = [-0.8_rk, 0.6_rk, 0.0_rk]
        CHECK_CLOSE(scene%rods(1)%d1, expected, 1.0e-16_rk, 0.0_rk, 'default d1')
        call parse(time // &
            "&rod n_elements = 4, geometry = 'polyline', points(4:9) = 0, 0, 0, 1, 0, 0," // nl // &
            '     ' // direct // ' /' // nl // &
            "&rod n_elements = 4, geometry = 'polyline', points = 0, 0, 0, 0, 0, 0, " // direct // &
            ' /' // nl, scene, errors, 2)
        joined = errors%joined()
        CHECK_CONTAINS(joined, "c.nml:2: &rod 'rod1' points: entry 1 is not given but a later one is", 'gap')
        CHECK_CONTAINS(joined, "c.nml:4: &rod 'rod2' points: points 1 and 2 coincide", 'coincide')
    end subroutine test_polyline_resolution

    ! A row without a curved reference rejects a helix or polyline rod, not a straight one.
    subroutine test_curved_reference_capability()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        type(capability_t) :: row
        character(len=:), allocatable :: fragment
        call parse(time // "&rod n_elements = 4, geometry = 'helix', helix_radius = 0.5," // &
            ' helix_pitch = 0.1, helix_turns = 2, ' // direct // ' /' // nl // arm, scene, errors, 0)
        call check_capabilities(scene, errors)
        CHECK_EQUAL(errors%count, 0, 'ph_director has a curved reference: ' // errors%joined())
        row = capability_of('ph_director')
        row%formulation = 'straight_only'
        row%curved_reference = .false.
        call check_rod_capabilities(scene, 1, row, errors)
        fragment = "c.nml:2: &rod geometry: a curved reference ('helix') is not available for " // &
            "formulation 'straight_only' (rod 'rod1'); available: 'straight'"
        CHECK_CONTAINS(errors%joined(), fragment, 'helix rejected')
        errors = error_list_t()
        call check_rod_capabilities(scene, 2, row, errors)
        CHECK_EQUAL(errors%count, 0, 'a straight rod passes')
    end subroutine test_curved_reference_capability

    ! Initial velocity: accepted on a free rod; on a rod with a clamped end (either end) and in a
    ! quasistatic run it is an error naming the rod's line and variable.
    subroutine test_initial_velocity_checks()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: joined, fragment
        call parse(time // rod_x // "a', velocity = 1, 0, 0, angular_velocity = 0, 2, 0, " // &
            direct // ' /' // nl, scene, errors, 0)
        call parse(time // rod_x // "a', angular_velocity = 0, 2, 0, " // direct // ' /' // nl // &
            "&bc rod = 'a', end = 'end', kind = 'clamped' /" // nl, scene, errors, 1)
        joined = errors%joined()
        fragment = "c.nml:2: &rod 'a' angular_velocity: (0.0, 2.0, 0.0) given, but the 'end' end is " // &
            'clamped (&bc at line 3)'
        CHECK_CONTAINS(joined, fragment, 'clamped')
        call parse(time // rod_x // "a', velocity = 0, 0, 0, " // direct // ' /' // nl // &
            "&bc rod = 'a', end = 'start', kind = 'clamped' /" // nl, scene, errors, 0)
        call parse('&time t_end = 1, dt = 0.5, quasistatic = .true. /' // nl // rod_x // &
            "a', velocity = 0, 1, 0, " // direct // ' /' // nl, scene, errors, 1)
        fragment = "c.nml:2: &rod 'a' velocity: (0.0, 1.0, 0.0) given, but a quasistatic run"
        CHECK_CONTAINS(errors%joined(), fragment, 'quasistatic')
    end subroutine test_initial_velocity_checks

    ! 'auto' chooses per system: rods a and b (joined, in the plane z = 0 with gravity along
    ! -e_y) get ph_planar; rod c, alone and pushed along e_z, ph_director; the origin stays
    ! 'auto' and the reason names the plane or the load. A cl_em_planar rod gets the default
    ! em_variant, a ph_planar rod none.
    subroutine test_auto_per_system()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text, expected
        ! Lines: 1 &run, 2 &time, 3-6 rods a-d, 7 &joint, 8-10 loads 1-3.
        text = "&run formulation_default = 'auto' /" // nl // time // &
            rod_x // "a', direction = 0, -1, 0, " // direct // ' /' // nl // &
            rod_x // "b', start = 0, -1, 0, " // direct // ' /' // nl // &
            rod_x // "c', start = 0, 0, 5, " // direct // ' /' // nl // &
            rod_x // "d', start = 0, 0, 9, formulation = 'cl_em_planar', " // direct // ' /' // nl // &
            "&joint rod_a = 'a', end_a = 'end', rod_b = 'b', end_b = 'start', kind = 'rigid' /" // nl // &
            "&load rod = 'a', where = 'distributed', force = 0, -1, 0 /" // nl // &
            "&load rod = 'c', where = 'end', force = 0, 0, 1 /" // nl // &
            "&load rod = 'c', where = 'distributed', force = 0, 1, 0 /" // nl
        call parse(text, scene, errors, 0)
        if (size(scene%rods) /= 4) return
        CHECK_EQUAL(trim(scene%rods(1)%formulation), 'ph_planar', 'a: planar')
        CHECK_EQUAL(trim(scene%rods(2)%formulation), 'ph_planar', 'b: planar')
        CHECK_EQUAL(trim(scene%rods(3)%formulation), 'ph_director', 'c: 3D')
        CHECK_EQUAL(trim(scene%rods(1)%formulation_origin), 'auto', 'origin kept')
        expected = 'lie in the plane through (0.0, 0.0, 0.0) with normal (0.0, 0.0, 1.0)'
        CHECK_CONTAINS(scene%rods(2)%formulation_reason, expected, 'b: reason')
        expected = '3D because load 3 (line 10): force (0.0, 1.0, 0.0) has a component along'
        CHECK_CONTAINS(scene%rods(3)%formulation_reason, expected, 'c: reason')
        CHECK_EQUAL(trim(scene%rods(4)%formulation_origin), 'rod', 'd: given')
        CHECK_EQUAL(trim(scene%rods(4)%em_variant), 'stander_stein', 'd: default em_variant')
        CHECK_EQUAL(len_trim(scene%rods(1)%em_variant), 0, 'a: no em_variant')
        errors = error_list_t()
        call check_capabilities(scene, errors)
        CHECK_EQUAL(errors%count, 0, 'auto picks what can run: ' // errors%joined())
    end subroutine test_auto_per_system

    ! One scene with several joint errors: all are reported, each with its line and variable.
    subroutine test_joint_errors_collected()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text, joined
        ! Lines: 1 &time, 2-3 rods a, b, 4-8 joints.
        text = time // &
            rod_x // "a', formulation = 'ph_planar', " // direct // ' /' // nl // &
            rod_x // "b', formulation = 'ph_planar', start = 1, 0, 0, " // direct // ' /' // nl // &
            "&joint rod_a = 'a', end_a = 'end', rod_b = 'x', end_b = 'start', kind = 'rigid' /" // nl // &
            "&joint rod_a = 'a', end_a = 'start', rod_b = 'a', end_b = 'start', kind = 'rigid' /" // nl // &
            "&joint rod_a = 'a', end_a = 'end', rod_b = 'b', end_b = 'start', kind = 'rigid' /" // nl // &
            "&joint rod_a = 'b', end_a = 'start', rod_b = 'a', end_b = 'end', kind = 'revolute' /" // nl // &
            "&joint rod_a = 'a', end_a = 'start', rod_b = 'b', end_b = 'end', kind = 'revolute' /" // nl
        call parse(text, scene, errors, 4)
        joined = errors%joined()
        CHECK_CONTAINS(joined, "c.nml:4: &joint rod_b: no rod is named 'x'", 'unknown rod')
        CHECK_CONTAINS(joined, "c.nml:5: &joint end_b: the joint ties the 'start' end of rod 'a'", 'self')
        CHECK_CONTAINS(joined, 'c.nml:7: &joint rod_b: redundant joint', 'redundant')
        CHECK_CONTAINS(joined, "c.nml:8: &joint end_b: the 'end' end of rod 'b' at (2.0, 0.0, 0.0)", 'apart')
    end subroutine test_joint_errors_collected

end module rs_test_io_input_check

!> Test program: runs the tests of rs_test_io_input_check; exits non-zero if any failed.
program test_input_check
    use rs_test_io_input_check, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_input_check
