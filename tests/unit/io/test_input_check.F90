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
!> the joint checks of one scene reported together. The inputs of se3_strand (seed 004): its
!> damping variables (refused for other formulations), relaxation (against the capability row
!> and quasistatics), driven ends moved by velocity or by pose as the formulation drives them
!> (several velocity drives on one end add up, anything else twice is an error) and its end
!> kinds, other at s = L than at s = 0. Bundles (issue 10): the plate's centre, the contact
!> radii, margin and skip derived, the joint axis normalized, one system, 'auto' choosing 3D for
!> contact or a hinge axis, and the bundle errors of one scene reported together. Each error is
!> checked for its file, line, group and variable.
module rs_test_io_input_check
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_list_t
    use rs_test_assert, only: run_test, assert_true, assert_equal, assert_contains, assert_close
    use rs_model_scene, only: scene_t, unset_real, unset_int, max_branches
    use rs_model_capabilities, only: capability_t
    use rs_formulations_registry, only: capability_of
    use rs_io_input_file, only: parse_scene
    use rs_io_input_check, only: check_capabilities, check_rod_capabilities
    use rs_model_coupling, only: coupled_systems
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
        call run_test('strand_damping', test_strand_damping)
        call run_test('relaxation', test_relaxation)
        call run_test('velocity_drives', test_velocity_drives)
        call run_test('drive_kind_per_formulation', test_drive_kind_per_formulation)
        call run_test('strand_end_kinds', test_strand_end_kinds)
        call run_test('bundle_resolution', test_bundle_resolution)
        call run_test('auto_with_bundles', test_auto_with_bundles)
        call run_test('bundle_errors_collected', test_bundle_errors_collected)
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

    !> A rod 'a' of formulation `formulation` (continued by `more`) as line 2 after `time`.
    function rod_on(formulation, more) result(text)
        character(len=*), intent(in) :: formulation, more
        character(len=:), allocatable :: text
        text = rod_x // "a', formulation = '" // formulation // "', " // more // direct // ' /' // nl
    end function rod_on

    ! The damping of seed 004 defaults to 0, is read on se3_strand rods and refused, when
    ! nonzero, on any other formulation (one error per variable); 0 given explicitly is fine.
    ! The damping every formulation may have (issue 26 item 1): kelvin_voigt_time resolves to
    ! six zeros, one value to all six, six in the order (EA, GA1, GA2, EI1, EI2, GJ); another
    ! count is an error; a row without damping refuses it, naming the rod.
    subroutine test_strand_damping()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        type(capability_t) :: row
        character(len=:), allocatable :: joined, fragment
        call parse(time // rod_on('se3_strand', ''), scene, errors, 0)
        if (size(scene%rods) /= 1) return
        CHECK_TRUE(scene%rods(1)%external_damping == 0.0_rk, 'external_damping defaults to 0')
        CHECK_TRUE(scene%rods(1)%internal_damping == 0.0_rk, 'internal_damping defaults to 0')
        CHECK_TRUE(all(scene%rods(1)%kelvin_voigt_time == 0.0_rk), 'kelvin_voigt_time defaults to 0')
        CHECK_TRUE(scene%rods(1)%drag == 0.0_rk, 'drag defaults to 0')
        CHECK_TRUE(scene%rods(1)%angular_drag == 0.0_rk, 'angular_drag defaults to 0')
        call parse(time // rod_on('se3_strand', 'external_damping = 0.1, internal_damping = 1e-4, ' // &
            'kelvin_voigt_time = 2e-3, drag = 0.5, ') // "&bc rod = 'a', end = 'start', kind = 'clamped' /" // nl, scene, errors, 0)
        CHECK_CLOSE(scene%rods(1)%external_damping, 0.1_rk, 0.0_rk, 0.0_rk, 'external_damping read')
        CHECK_CLOSE(scene%rods(1)%internal_damping, 1.0e-4_rk, 0.0_rk, 0.0_rk, 'internal_damping read')
        CHECK_TRUE(all(scene%rods(1)%kelvin_voigt_time == 2.0e-3_rk), 'one kelvin_voigt_time is all six')
        CHECK_CLOSE(scene%rods(1)%drag, 0.5_rk, 0.0_rk, 0.0_rk, 'drag read')
        call check_capabilities(scene, errors)
        CHECK_EQUAL(errors%count, 0, 'se3_strand takes its damping: ' // errors%joined())
        call parse(time // rod_on('se3_strand', 'kelvin_voigt_time = 1, 2, 3, 4, 5, 6, '), scene, &
            errors, 0)
        CHECK_TRUE(all(scene%rods(1)%kelvin_voigt_time == [1, 2, 3, 4, 5, 6]), 'six times in order')
        call parse(time // rod_on('se3_strand', 'kelvin_voigt_time = 1, 2, 3, '), scene, errors, 1)
        fragment = "c.nml:2: &rod 'a' kelvin_voigt_time: 3 value(s) given; give one (every " // &
            "stress component) or six (EA, GA1, GA2, EI1, EI2, GJ in this order)"
        CHECK_CONTAINS(errors%joined(), fragment, 'three times refused')
        call parse(time // rod_on('se3_pg', 'internal_damping = 1e-4, kelvin_voigt_time = 0, ' // &
            'external_damping = 0.5, '), scene, errors, 0)
        call check_capabilities(scene, errors)
        CHECK_EQUAL(errors%count, 2, 'two nonzero damping variables refused: ' // errors%joined())
        joined = errors%joined()
        fragment = "c.nml:2: &rod 'a' internal_damping: only used with formulation 'se3_strand' " // &
            "(this rod runs on 'se3_pg'); remove it"
        CHECK_CONTAINS(joined, fragment, 'internal_damping refused')
        fragment = "c.nml:2: &rod 'a' external_damping: only used with formulation 'se3_strand'"
        CHECK_CONTAINS(joined, fragment, 'external_damping refused')
        CHECK_TRUE(index(joined, 'kelvin_voigt_time') == 0, 'a zero kelvin_voigt_time is not refused')
        call parse(time // rod_on('se3_strand', 'kelvin_voigt_time = -1, '), scene, errors, 1)
        fragment = 'c.nml:2: &rod kelvin_voigt_time: value -1 out of range; allowed: >= 0.0'
        CHECK_CONTAINS(errors%joined(), fragment, 'negative refused')
        call parse(time // rod_on('se3_pg', 'angular_drag = 1e-3, '), scene, errors, 0)
        row = capability_of('se3_pg')
        row%formulation = 'undamped'
        row%damping = .false.
        call check_rod_capabilities(scene, 1, row, errors)
        fragment = "c.nml:2: &rod kelvin_voigt_time, drag, angular_drag: damping is not " // &
            "available for formulation 'undamped' (rod 'a') (docs/user/capabilities.md)"
        CHECK_CONTAINS(errors%joined(), fragment, 'a row without damping refuses it')
    end subroutine test_strand_damping

    ! &time relaxation: kinetic_energy_tol defaults to 1e-12 J; se3_strand has relaxation and
    ! se3_pg not (a capability error naming the rod); with quasistatic it is an error of the
    ! scene whatever the formulation; kinetic_energy_tol must be positive, and a value other than
    ! the default is refused without relaxation (it would be ignored).
    subroutine test_relaxation()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: fragment
        character(len=*), parameter :: relax = '&time t_end = 1, dt = 0.5, relaxation = .true. /' // nl
        call parse(relax // rod_on('se3_strand', 'external_damping = 0.1, ') // "&bc rod = 'a', end = 'start', kind = 'clamped' /" // nl, scene, &
            errors, 0)
        CHECK_TRUE(scene%time%relaxation, 'relaxation read')
        CHECK_CLOSE(scene%time%kinetic_energy_tol, 1.0e-12_rk, 0.0_rk, 0.0_rk, 'default tolerance')
        call check_capabilities(scene, errors)
        CHECK_EQUAL(errors%count, 0, 'se3_strand relaxes: ' // errors%joined())
        call parse(relax // rod_on('se3_pg', ''), scene, errors, 0)
        call check_capabilities(scene, errors)
        CHECK_EQUAL(errors%count, 1, 'se3_pg does not relax: ' // errors%joined())
        fragment = "c.nml: &time relaxation: statics by damped dynamics is not available for " // &
            "formulation 'se3_pg' (rod 'a') (docs/user/capabilities.md)"
        CHECK_CONTAINS(errors%joined(), fragment, 'capability error')
        call parse('&time t_end = 1, dt = 0.5, relaxation = .true., quasistatic = .true. /' // nl // &
            rod_on('se3_pg', ''), scene, errors, 1)
        fragment = 'c.nml: &time relaxation: statics by damped dynamics needs the inertia that ' // &
            'quasistatic = .true. drops'
        CHECK_CONTAINS(errors%joined(), fragment, 'not with quasistatic')
        call parse('&time t_end = 1, dt = 0.5, relaxation = .true., kinetic_energy_tol = 1e-9 /' // &
            nl // rod_on('se3_strand', ''), scene, errors, 0)
        CHECK_CLOSE(scene%time%kinetic_energy_tol, 1.0e-9_rk, 0.0_rk, 0.0_rk, 'tolerance read')
        call parse('&time t_end = 1, dt = 0.5, kinetic_energy_tol = 0 /' // nl // &
            rod_on('se3_strand', ''), scene, errors, 1)
        CHECK_CONTAINS(errors%joined(), 'c.nml:1: &time kinetic_energy_tol: value 0 out of range', '> 0')
        call parse('&time t_end = 1, dt = 0.5, kinetic_energy_tol = 1e-9 /' // nl // &
            rod_on('se3_strand', ''), scene, errors, 1)
        fragment = 'c.nml: &time kinetic_energy_tol: 1.0e-09 given, but it is only used with ' // &
            'relaxation = .true.; remove it or set relaxation'
        CHECK_CONTAINS(errors%joined(), fragment, 'tolerance without relaxation')
        call parse('&time t_end = 1, dt = 0.5, kinetic_energy_tol = 1e-12 /' // nl // &
            rod_on('se3_strand', ''), scene, errors, 0)
    end subroutine test_relaxation

    ! se3_strand drives its start by velocity: two driven &bc on that end add up (a vertical
    ! sine plus a ramped spin, seed 004 §3.3) and a constant velocity need not start at 0; a
    ! clamp besides a driven &bc is still twice, and so are two driven &bc on an se3_pg end.
    subroutine test_velocity_drives()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text, fragment
        real(rk), parameter :: oscillation_velocity(3) = [0.0_rk, 0.0_rk, 0.5655_rk]
        real(rk), parameter :: spin_rate(3) = [0.0_rk, 0.0_rk, 50.27_rk]
        character(len=*), parameter :: oscillation = "&bc rod = 'a', end = 'start', kind = 'driven', " // &
            "velocity = 0, 0, 0.5655, time_function = 'sine', t_off = 0.2222222222222222 /" // nl
        character(len=*), parameter :: spin = "&bc rod = 'a', end = 'start', kind = 'driven', " // &
            "angular_velocity = 0, 0, 50.27, time_function = 'ramp', t_on = 12, t_off = 20 /" // nl
        text = time // rod_on('se3_strand', '') // oscillation // spin
        call parse(text, scene, errors, 0)
        if (size(scene%bcs) /= 2) return
        CHECK_CLOSE(scene%bcs(1)%velocity, oscillation_velocity, 0.0_rk, 0.0_rk, 'velocity read')
        CHECK_CLOSE(scene%bcs(2)%angular_velocity, spin_rate, 0.0_rk, 0.0_rk, 'spin read')
        call check_capabilities(scene, errors)
        CHECK_EQUAL(errors%count, 0, 'two velocity drives on one end: ' // errors%joined())
        call parse(time // rod_on('se3_strand', '') // "&bc rod = 'a', end = 'start', " // &
            "kind = 'driven', velocity = 1, 0, 0 /" // nl, scene, errors, 0)
        call check_capabilities(scene, errors)
        CHECK_EQUAL(errors%count, 0, 'a constant velocity drive (f(0) = 1): ' // errors%joined())
        call parse(time // rod_on('se3_strand', '') // oscillation // &
            "&bc rod = 'a', end = 'start', kind = 'clamped' /" // nl, scene, errors, 1)
        fragment = "c.nml:4: &bc end: the 'start' end of rod 'a' already has a support (line 3); " // &
            'only driven ends may be given more than once (their velocities add up)'
        CHECK_CONTAINS(errors%joined(), fragment, 'clamp besides a drive')
        text = "&bc rod = 'a', end = 'start', kind = 'driven', rotation = 0, 0, 1, " // &
            "time_function = 'ramp', t_off = 1 /" // nl
        call parse(time // rod_on('se3_pg', '') // text // text, scene, errors, 1)
        fragment = "c.nml:4: &bc end: the 'start' end of rod 'a' already has a support (line 3)"
        CHECK_CONTAINS(errors%joined(), fragment, 'two pose drives')
        CHECK_TRUE(index(errors%joined(), 'velocities add up') == 0, 'no velocity note for se3_pg')
        call parse(time // rod_on('se3_strand', '') // "&bc rod = 'a', end = 'start', " // &
            "kind = 'driven', velocity = 1, 0, 0, time_function = 'sine' /" // nl, scene, errors, 1)
        CHECK_CONTAINS(errors%joined(), "c.nml:3: &bc t_off: required by time_function = 'sine'", 'sine')
    end subroutine test_velocity_drives

    ! A driven end is moved as its formulation drives ends: se3_pg by pose, se3_strand by
    ! velocity; both at once, none, or either on a clamp is an error whatever the formulation.
    subroutine test_drive_kind_per_formulation()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: fragment
        character(len=*), parameter :: driven = "&bc rod = 'a', end = 'start', kind = 'driven', " // &
            "time_function = 'ramp', t_off = 1, "
        call parse(time // rod_on('se3_pg', '') // driven // 'angular_velocity = 0, 0, 1 /' // nl, &
            scene, errors, 0)
        call check_capabilities(scene, errors)
        CHECK_EQUAL(errors%count, 1, 'velocity drive on se3_pg: ' // errors%joined())
        fragment = "c.nml:3: &bc velocity, angular_velocity: formulation 'se3_pg' drives an end by " // &
            'its pose; give displacement and rotation instead (docs/user/capabilities.md)'
        CHECK_CONTAINS(errors%joined(), fragment, 'se3_pg drives the pose')
        call parse(time // rod_on('se3_strand', '') // driven // 'displacement = 0, 0, 1 /' // nl, &
            scene, errors, 0)
        call check_capabilities(scene, errors)
        CHECK_EQUAL(errors%count, 1, 'pose drive on se3_strand: ' // errors%joined())
        fragment = "c.nml:3: &bc displacement, rotation: formulation 'se3_strand' drives an end by " // &
            'its velocity; give velocity and angular_velocity instead'
        CHECK_CONTAINS(errors%joined(), fragment, 'se3_strand drives the velocity')
        call parse(time // rod_on('se3_pg', '') // driven // 'velocity = 1, 0, 0, rotation = 0, 0, 1 /' // &
            nl, scene, errors, 1)
        fragment = 'c.nml:3: &bc velocity, angular_velocity: given with displacement or rotation'
        CHECK_CONTAINS(errors%joined(), fragment, 'not both')
        call parse(time // rod_on('se3_strand', '') // driven // "t_on = 0 /" // nl, scene, errors, 1)
        fragment = 'c.nml:3: &bc kind: a driven end needs a displacement or a rotation (formulations ' // &
            'that drive the pose) or a velocity or an angular_velocity'
        CHECK_CONTAINS(errors%joined(), fragment, 'no motion')
        call parse(time // rod_on('se3_strand', '') // "&bc rod = 'a', end = 'start', " // &
            "kind = 'clamped', velocity = 1, 0, 0 /" // nl, scene, errors, 1)
        fragment = "c.nml:3: &bc velocity, angular_velocity: only a driven end moves (kind = " // &
            "'driven'), this one is 'clamped'"
        CHECK_CONTAINS(errors%joined(), fragment, 'velocity on a clamp')
    end subroutine test_drive_kind_per_formulation

    ! se3_strand (methods/se3_strands.md §3.4): clamped, driven or free at s = 0, free only at
    ! s = L, with a message naming the end and both lists; other ends keep the plain message; a
    ! start without &bc (free, issue 26 item 4) is accepted.
    subroutine test_strand_end_kinds()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: fragment
        call parse(time // rod_on('se3_strand', '') // "&bc rod = 'a', end = 'start', kind = 'clamped' /" // &
            nl // "&bc rod = 'a', end = 'end', kind = 'free' /" // nl, scene, errors, 0)
        call check_capabilities(scene, errors)
        CHECK_EQUAL(errors%count, 0, 'clamped start, free end: ' // errors%joined())
        call parse(time // rod_on('se3_strand', '') // "&bc rod = 'a', end = 'end', kind = 'clamped' /" // &
            nl // "&bc rod = 'a', end = 'start', kind = 'clamped' /" // nl, scene, errors, 0)
        call check_capabilities(scene, errors)
        CHECK_EQUAL(errors%count, 1, 'clamped end refused: ' // errors%joined())
        fragment = "c.nml:3: &bc kind: a 'clamped' end is not available at the 'end' end (s = L) " // &
            "for formulation 'se3_strand'; available there: free (at the 'start' end: " // &
            'clamped|driven|free); se3_strand prescribes the motion or no stress at s = 0 and ' // &
            'the stress at s = L (methods/se3_strands.md §3.4; docs/theory/se3_strand.md) ' // &
            '(docs/user/capabilities.md)'
        CHECK_CONTAINS(errors%joined(), fragment, 'names the end and both lists')
        call parse(time // rod_on('se3_strand', '') // "&bc rod = 'a', end = 'start', kind = 'pinned' /" // &
            nl, scene, errors, 0)
        call check_capabilities(scene, errors)
        fragment = "c.nml:3: &bc kind: a 'pinned' end is not available for formulation " // &
            "'se3_strand'; available: clamped|driven|free (docs/user/capabilities.md)"
        CHECK_CONTAINS(errors%joined(), fragment, 'pinned start: the plain message')
        call parse(time // rod_on('se3_strand', ''), scene, errors, 0)
        call check_capabilities(scene, errors)
        CHECK_EQUAL(errors%count, 0, 'free start accepted: ' // errors%joined())
    end subroutine test_strand_end_kinds

    ! Bundles (issue 10), lines: 1 &time, 2-4 rods a, b, c, 5 &joint, 6 &plate, 7 &contact.
    ! The plate's rods land in order and its centre defaults to the mean of the tied ends,
    ! (1, 0, 0) and (2, 0.1, 0), except the given centre(3); the joint axis is normalized; the
    ! circle's and the tube's contact radii are their radii, c's is given; the margin is the
    ! largest contact radius 0.05 and skip = ceiling(3 0.05 / 0.1) + 1 = 3 (c's elements are the
    ! shortest, 0.5 / 5); every rod is in one system; everything runs on ph_director.
    subroutine test_bundle_resolution()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        integer, allocatable :: system_of(:), first(:), members(:)
        real(rk), parameter :: centre(3) = [1.5_rk, 0.05_rk, 5.0_rk], e_z(3) = [0.0_rk, 0.0_rk, 1.0_rk]
        real(rk), parameter :: radii(3) = [0.01_rk, 0.03_rk, 0.05_rk]
        text = time // &
            rod_x // "a', section = 'circle', radius = 0.01, E = 1e9, nu = 0.3, " // &
            'density = 1000 /' // nl // &
            "&rod name = 'b', n_elements = 10, length = 2, start = 0, 0.1, 0, section = 'tube', " // &
            'radius = 0.03, inner_radius = 0.02, E = 1e9, nu = 0.3, density = 1000 /' // nl // &
            "&rod name = 'c', n_elements = 5, length = 0.5, start = -0.5, 0, 0, contact_radius = " // &
            '0.05, ' // direct // ' /' // nl // &
            "&joint rod_a = 'c', end_a = 'end', rod_b = 'a', end_b = 'start', kind = 'revolute', " // &
            'axis = 0, 0, 2 /' // nl // &
            "&plate name = 'head', rods = 'a', 'b', end = 'end', centre(3) = 5 /" // nl // &
            '&contact stiffness = 1e9 /' // nl
        call parse(text, scene, errors, 0)
        if (size(scene%rods) /= 3 .or. size(scene%plates) /= 1) return
        CHECK_EQUAL(scene%plates(1)%input_line, 6, 'plate line')
        CHECK_EQUAL(trim(scene%plates(1)%rods(1)) // ',' // trim(scene%plates(1)%rods(2)), 'a,b', 'rods')
        CHECK_EQUAL(len_trim(scene%plates(1)%rods(3)), 0, 'two rods')
        CHECK_CLOSE(scene%plates(1)%centre, centre, 1.0e-15_rk, 0.0_rk, 'centre: mean, and centre(3)')
        CHECK_CLOSE(scene%joints(1)%axis, e_z, 0.0_rk, 0.0_rk, 'axis normalized')
        CHECK_TRUE(scene%contact%given, 'contact given')
        CHECK_EQUAL(scene%contact%input_line, 7, 'contact line')
        CHECK_CLOSE(scene%rods%contact_radius, radii, 0.0_rk, 0.0_rk, 'radii')
        CHECK_CLOSE(scene%contact%margin, 0.05_rk, 0.0_rk, 0.0_rk, 'margin: largest radius')
        CHECK_EQUAL(scene%contact%skip, 3, 'skip: ceiling(3 r_max / h_min) + 1')
        CHECK_EQUAL(scene%contact%points_per_element, unset_int, 'points per element: the formulation''s')
        CHECK_TRUE(scene%contact%self_contact, 'self contact by default')
        CHECK_CLOSE(scene%contact%mu, 0.0_rk, 0.0_rk, 0.0_rk, 'frictionless by default')
        call coupled_systems(scene, system_of, first, members)
        CHECK_TRUE(all(system_of == 1), 'one system')
        errors = error_list_t()
        call check_capabilities(scene, errors)
        CHECK_EQUAL(errors%count, 0, 'ph_director runs bundles: ' // errors%joined())
        ! Given margin, skip and points are kept (0 is allowed for margin and skip); the default
        ! skip does not depend on the margin: ceiling(3 0.0625 / (1 / 64)) + 1 = 13 (exact).
        text = time // rod_x // "a', contact_radius = 0.01, " // direct // ' /' // nl // &
            '&contact stiffness = 1e9, margin = 0, skip = 0, points_per_element = 5 /' // nl // &
            "&rod name = 'b', n_elements = 64, length = 1, start = 0, 1, 0, contact_radius = 0.0625, " // &
            direct // ' /' // nl
        call parse(text, scene, errors, 0)
        CHECK_CLOSE(scene%contact%margin, 0.0_rk, 0.0_rk, 0.0_rk, 'margin given')
        CHECK_EQUAL(scene%contact%skip, 0, 'skip given')
        CHECK_EQUAL(scene%contact%points_per_element, 5, 'points given')
        text = replace_first(text, ', skip = 0', '')
        call parse(text, scene, errors, 0)
        CHECK_EQUAL(scene%contact%skip, 13, 'skip = ceiling(3 0.0625 / (1 / 64)) + 1')
    end subroutine test_bundle_resolution

    ! 'auto' on a planar pair: ph_planar without bundle parts, ph_director with &contact or a
    ! revolute joint with an axis (ph_planar cannot run them), and the reason says why.
    subroutine test_auto_with_bundles()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: pair, joint, why
        pair = "&run formulation_default = 'auto' /" // nl // time // &
            rod_x // "a', contact_radius = 0.01, " // direct // ' /' // nl // &
            rod_x // "b', start = 1, 0, 0, contact_radius = 0.01, " // direct // ' /' // nl
        joint = "&joint rod_a = 'a', end_a = 'end', rod_b = 'b', end_b = 'start', kind = 'revolute'"
        call parse(pair // '&contact stiffness = 1e9 /' // nl, scene, errors, 0)
        CHECK_EQUAL(trim(scene%rods(1)%formulation), 'ph_director', 'contact: 3D')
        why = "because ph_planar cannot run them: &contact: rod-rod contact is not available for " // &
            "formulation 'ph_planar' (rod 'a')"
        CHECK_CONTAINS(scene%rods(2)%formulation_reason, why, 'why')
        pair = replace_first(replace_first(pair, 'contact_radius = 0.01, ', ''), &
            'contact_radius = 0.01, ', '')
        call parse(pair // joint // ' /' // nl, scene, errors, 0)
        CHECK_EQUAL(trim(scene%rods(1)%formulation), 'ph_planar', 'pin in the plane: planar')
        errors = error_list_t()
        call check_capabilities(scene, errors)
        CHECK_EQUAL(errors%count, 0, 'planar revolute joint without axis: ' // errors%joined())
        call parse(pair // joint // ', axis = 0, 1, 0 /' // nl, scene, errors, 0)
        CHECK_EQUAL(trim(scene%rods(2)%formulation), 'ph_director', 'hinge with an axis: 3D')
        CHECK_CONTAINS(scene%rods(1)%formulation_reason, '&joint axis: formulation ''ph_planar''', 'axis')
        errors = error_list_t()
        call check_capabilities(scene, errors)
        CHECK_EQUAL(errors%count, 0, 'ph_director hinge: ' // errors%joined())
    end subroutine test_auto_with_bundles

    ! One scene with several bundle errors: all are reported, each with its line and variable.
    ! Lines: 1 &time, 2-3 rods a, b, 4 &bc, 5-6 joints, 7-8 plates, 9 &contact (11 errors).
    subroutine test_bundle_errors_collected()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text, joined
        text = time // rod_x // "a', " // direct // ' /' // nl // &
            rod_x // "b', start = 1, 0, 0, " // direct // ' /' // nl // &
            "&bc rod = 'b', end = 'end', kind = 'clamped' /" // nl // &
            "&joint rod_a = 'a', end_a = 'end', rod_b = 'b', end_b = 'start', kind = 'spherical', " // &
            'axis = 1, 0, 0 /' // nl // &
            "&joint rod_a = 'a', end_a = 'start', rod_b = 'b', end_b = 'end', kind = 'revolute' /" // nl // &
            "&plate name = 'p', rods = 'a', 'bb', 'a', end = 'end' /" // nl // &
            "&plate name = 'p', rods = 'b', end = 'end', displacement = 0, 0, 1 /" // nl // &
            '&contact stiffness = 1e9 /' // nl
        call parse(text, scene, errors, 11)
        joined = errors%joined()
        CHECK_CONTAINS(joined, "c.nml:5: &joint axis: only a revolute joint turns about an axis", 'axis')
        CHECK_CONTAINS(joined, "c.nml:6: &joint end_b: the 'end' end of rod 'b' at (2.0, 0.0, 0.0)", 'apart')
        CHECK_CONTAINS(joined, "c.nml:7: &plate 'p' rods: no rod is named 'bb'; did you mean", 'unknown')
        CHECK_CONTAINS(joined, "c.nml:7: &plate 'p' rods: the 'end' end of rod 'a' is also tied", 'joint')
        CHECK_CONTAINS(joined, "c.nml:7: &plate 'p' rods: rod 'a' is listed twice", 'twice')
        CHECK_CONTAINS(joined, "c.nml:8: &plate 'p' name: 'p' is already the name", 'name')
        CHECK_CONTAINS(joined, "c.nml:8: &plate 'p' rods: the 'end' end of rod 'b' has a 'clamped' &bc", 'bc')
        CHECK_CONTAINS(joined, "c.nml:8: &plate 'p' time_function: f(0) = 1.0", 'f(0)')
        CHECK_CONTAINS(joined, "c.nml:8: &plate 'p' rods: the 'end' end of rod 'b' is also tied", 'joint b')
        CHECK_CONTAINS(joined, "c.nml:2: &rod 'a' contact_radius: required with &contact (line 9)", 'r')
        CHECK_CONTAINS(joined, "c.nml:3: &rod 'b' contact_radius: required with &contact (line 9)", 'r b')
    end subroutine test_bundle_errors_collected

    function replace_first(text, old, new) result(out)
        character(len=*), intent(in) :: text, old, new
        character(len=:), allocatable :: out
        integer :: at
        at = index(text, old)
        out = text
        if (at > 0) out = text(1:at - 1) // new // text(at + len(old):)
    end function replace_first

end module rs_test_io_input_check

!> Test program: runs the tests of rs_test_io_input_check; exits non-zero if any failed.
program test_input_check
    use rs_test_io_input_check, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_input_check
