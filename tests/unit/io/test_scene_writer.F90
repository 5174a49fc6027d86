#include "rs_assert.h"
!> Unit tests of rs_io_scene_writer (resolved_scene_text): the resolved text of a parsed scene
!> parses again without errors to a scene equal to the first in every field (reals bitwise,
!> compared through their bit patterns), and writing that second scene gives the identical text
!> (DESIGN.md 6: "the resolved input ... is echoed and stored"; the module promises "a form
!> rodsolve reads back to the same scene"). Also the form of the text: one block per group
!> occurrence, reference spelling of names, unset variables and the hidden input_line left out,
!> only the given entries of tables and Maxwell arrays; and tables filled to capacity
!> (max_table points) round-trip. The bundle groups (issue 10): &plate and &contact, a joint
!> axis, contact radii and a helix phase round-trip; helix_phase is left out for straight rods,
!> the unused places of a plate's rods and an absent &contact are not written.
module rs_test_io_scene_writer
    use rs_core_kinds, only: rk, i8
    use rs_core_error, only: error_list_t
    use rs_test_assert, only: run_test, assert_true, assert_equal, assert_contains
    use rs_core_strings, only: str
    use rs_model_scene, only: scene_t, rod_input_t, bc_input_t, load_input_t, actuator_input_t, &
        joint_input_t, plate_input_t, contact_input_t, &
        max_table, max_polyline_points
    use rs_io_input_file, only: parse_scene
    use rs_io_scene_writer, only: resolved_scene_text
    implicit none
    private

    public :: run_all_tests

    character(len=*), parameter :: nl = new_line('a')

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('round_trip_every_group', test_round_trip_every_group)
        call run_test('round_trip_defaults_only', test_round_trip_defaults_only)
        call run_test('resolved_text_form', test_resolved_text_form)
        call run_test('round_trip_oblique_directors', test_round_trip_oblique_directors)
        call run_test('round_trip_section_rod', test_round_trip_section_rod)
        call run_test('round_trip_full_tables', test_round_trip_full_tables)
        call run_test('round_trip_curved_rods', test_round_trip_curved_rods)
        call run_test('round_trip_bundle', test_round_trip_bundle)
        call run_test('bundle_text_form', test_bundle_text_form)
    end subroutine run_all_tests

    !> A scene that sets (almost) every variable of every implemented group to a value other
    !> than its default, with reals that need all 17 digits or a three-digit exponent, and
    !> strings with quotes, "!" and "/"; rods with directly given stiffnesses along the axes.
    function every_group() result(text)
        character(len=:), allocatable :: text
        text = "&run title = 'say ""hi"": it''s a / test ! really'," // nl // &
            "     formulation_default = 'se3_pg', log_level = 'debug' /" // nl // &
            '&time t_end = 3.5, dt = 1e-3, quasistatic = .true. /' // nl // &
            '&solver newton_atol = 1e-12, newton_rtol = 1e-6, max_newton = 40,' // nl // &
            "  max_cutbacks = 3, petsc_options = '-ksp_type gmres -pc_type none' /" // nl // &
            "&output path = 'res/every.h5', stride = 5, fields = 'position,stress'," // nl // &
            '        flush_every = 3, xdmf = .false. /' // nl // &
            "&rod name = 'left', formulation = 'ph_planar', n_elements = 12," // nl // &
            '     degree = 1, n_gauss = 3, start = -1.5, 0.25, 1e-7,' // nl // &
            '     direction = 0, 0, -4, length = 2.75, EA = 12345.678901234567,' // nl // &
            '     GA1 = 3.3e150, GA2 = 0.7, EI1 = 0.1, EI2 = 0.3,' // nl // &
            '     GJ = 0.3333333333333333, rhoA = 0.2, rhoI1 = 1e-5, rhoI2 = 1.5e-120,' // nl // &
            "     prestressed = .true., constraint = 'inextensible', em_variant = 'ph_irreducible'," // nl // &
            '     maxwell_fraction = 0.25, 0.125, 0.0625, maxwell_tau_E = 1e-3, 0.5, 20,' // nl // &
            '     maxwell_tau_G(2) = 0.75 /' // nl // &
            '&rod n_elements = 3, length = 1, d1 = 0, 0, -2, EA = 1, GA1 = 2, GA2 = 3,' // nl // &
            '     EI1 = 4, EI2 = 5, GJ = 6, rhoA = 7, rhoI1 = 8, rhoI2 = 9 /' // nl // &
            "&rod name = 'right', formulation = 'ph_planar', n_elements = 2, n_gauss = 3," // nl // &
            "     em_variant = 'ph_irreducible', start = -1.5, 0.25, -2.7499999, length = 0.5," // nl // &
            '     EA = 1, GA1 = 2, GA2 = 3, EI1 = 4, EI2 = 5, GJ = 6, rhoA = 7, rhoI1 = 8, rhoI2 = 9 /' // nl // &
            "&bc rod = 'left', end = 'end', kind = 'pinned' /" // nl // &
            "&bc rod = 'left', end = 'start', kind = 'body', mass = 0.5, centre = 0.01, 0, -2e-3," // nl // &
            "    inertia = 1e-4, 2e-4, 2.5e-4, inertia_products = 0, 1e-6, 0 /" // nl // &
            "&bc rod = 'rod2', end = 'start', kind = 'driven', rotation = 0.5, 0, -1.25," // nl // &
            "    displacement = 0, 1e-3, 0, time_function = 'ramp', t_on = 0.25, t_off = 2 /" // nl // &
            "&load rod = 'left', where = 'end', force = 1.1, -2.2, 3.3," // nl // &
            "      moment = 0, 0, 0.1, frame = 'follower', time_function = 'table'," // nl // &
            '      table_times = 0, 0.1, 0.7, 3.5, table_values = 0, 1, -1, 2 /' // nl // &
            "&load rod = 'rod2', where = 'distributed', force = 0, 1, 0," // nl // &
            "      time_function = 'hat', t_on = 0.5, t_off = 1.25 /" // nl // &
            "&load where = 'gravity', acceleration = 0, -9.81, 0 /" // nl // &
            "&actuator rod = 'left', kind = 'pneumatic', offset = 1e-3, -2.5e-3," // nl // &
            '          area = 7.0685834705770345e-4, pressure = -12345.5,' // nl // &
            "          time_function = 'pulse', t_on = 0.25, t_off = 1.75 /" // nl // &
            "&actuator rod = 'rod2', kind = 'Tendon', offset = 0, 0.01, tension = 0.1," // nl // &
            "          time_function = 'table', table_times = 0, 0.5, 3.5," // nl // &
            '          table_values = 0, 1, 0.3333333333333333 /' // nl // &
            "&joint rod_a = 'left', end_a = 'end', rod_b = 'right', end_b = 'start', kind = 'Rigid' /" // nl
    end function every_group

    !> Parse, write, parse the written text and write again: both parses without errors, the
    !> scenes equal field by field and the two texts identical.
    subroutine check_round_trip(text, file)
        character(len=*), intent(in) :: text, file
        type(scene_t) :: first, second
        type(error_list_t) :: errors
        character(len=:), allocatable :: text1, text2
        call parse_scene(text, file, first, errors)
        CHECK_EQUAL(errors%count, 0, 'original scene valid: ' // errors%joined())
        if (errors%count > 0) return
        text1 = resolved_scene_text(first)
        errors = error_list_t()
        call parse_scene(text1, file, second, errors)
        CHECK_EQUAL(errors%count, 0, 'resolved text parses without errors: ' // errors%joined())
        if (errors%count > 0) return
        call check_same_scene(first, second)
        text2 = resolved_scene_text(second)
        CHECK_TRUE(text2 == text1, 'second resolve and write gives identical text')
        if (text2 /= text1) call show_first_difference(text1, text2)
    end subroutine check_round_trip

    subroutine show_first_difference(a, b)
        character(len=*), intent(in) :: a, b
        integer :: i, line_start
        line_start = 1
        do i = 1, min(len(a), len(b))
            if (a(i:i) /= b(i:i)) exit
            if (a(i:i) == nl) line_start = i + 1
        end do
        CHECK_EQUAL(b(line_start:min(len(b), i + 40)), a(line_start:min(len(a), i + 40)), 'diff')
    end subroutine show_first_difference

    subroutine test_round_trip_every_group()
        call check_round_trip(every_group(), 'cases/every_group.nml')
    end subroutine test_round_trip_every_group

    ! A minimal scene: the written defaults read back as the same defaults.
    subroutine test_round_trip_defaults_only()
        call check_round_trip('&time t_end = 1, dt = 0.5 /' // nl // &
            '&rod n_elements = 1, length = 1, EA = 1, GA1 = 1, GA2 = 1, EI1 = 1, EI2 = 1,' // &
            ' GJ = 1, rhoA = 1, rhoI1 = 1, rhoI2 = 1 /' // nl, 'minimal.nml')
    end subroutine test_round_trip_defaults_only

    ! The documented form: &group blocks in the order run, time, solver, output, rods, bcs, loads;
    ! "name = value" lines with the reference spelling; unset variables and input_line absent.
    subroutine test_resolved_text_form()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        call parse_scene(every_group(), 'every_group.nml', scene, errors)
        CHECK_EQUAL(errors%count, 0, 'valid scene')
        text = resolved_scene_text(scene)
        CHECK_EQUAL(occurrences(text, nl // '&run' // nl), 1, '&run block')
        CHECK_EQUAL(occurrences(text, nl // '&rod' // nl), 3, 'one &rod block per rod')
        CHECK_EQUAL(occurrences(text, nl // '&bc' // nl), 3, 'one &bc block per bc')
        CHECK_EQUAL(occurrences(text, nl // '&load' // nl), 3, 'one &load block per load')
        CHECK_EQUAL(occurrences(text, nl // '&actuator' // nl), 2, 'one &actuator block per actuator')
        CHECK_EQUAL(occurrences(text, nl // '&joint' // nl), 1, 'one &joint block per joint')
        CHECK_EQUAL(occurrences(text, nl // '/' // nl), 16, 'every block closed')
        CHECK_EQUAL(occurrences(text, nl // '    mass = '), 1, 'a mass for the body''s end only')
        CHECK_TRUE(index(text, '&actuator') < index(text, '&joint'), 'actuators before joints')
        CHECK_CONTAINS(text, nl // "    rod_b = 'right'" // nl, 'joint rod')
        CHECK_CONTAINS(text, nl // "    kind = 'rigid'" // nl // '/', 'joint kind in lower case')
        CHECK_CONTAINS(text, nl // "    em_variant = 'ph_irreducible'" // nl, 'em_variant')
        CHECK_EQUAL(occurrences(text, 'em_variant'), 2, 'a blank em_variant is left out')
        CHECK_TRUE(index(text, '&load') < index(text, '&actuator'), 'loads before actuators')
        CHECK_TRUE(index(text, '&time') < index(text, '&solver'), 'time before solver')
        CHECK_TRUE(index(text, '&output') < index(text, '&rod'), 'output before rods')
        CHECK_TRUE(index(text, '&bc') < index(text, '&load'), 'bcs before loads')
        CHECK_CONTAINS(text, nl // '    rhoI1 = ', 'reference spelling of rhoI1')
        CHECK_CONTAINS(text, nl // '    EA = ', 'reference spelling of EA')
        CHECK_CONTAINS(text, nl // '    GJ = 0.3333333333333333' // nl, 'shortest real')
        CHECK_CONTAINS(text, nl // '    n_elements = 12' // nl, 'integer')
        CHECK_CONTAINS(text, nl // '    xdmf = .false.' // nl, 'logical')
        CHECK_CONTAINS(text, nl // "    name = 'left'" // nl, 'string without padding')
        CHECK_EQUAL(occurrences(text, 'input_line'), 0, 'input_line is not an input variable')
        CHECK_EQUAL(occurrences(text, 'radius'), 0, 'unset radius left out')
        CHECK_EQUAL(occurrences(text, 'density'), 0, 'unset density left out')
        CHECK_EQUAL(occurrences(text, 't_off'), 3, 't_off only where it was given (a load, an actuator, the driven bc)')
        CHECK_CONTAINS(text, nl // '    table_times = 0.0, 0.1, 0.7, 3.5' // nl, 'given entries only')
        CHECK_CONTAINS(text, nl // '    table_values = 0.0, 1.0, 0.3333333333333333' // nl, 'actuator table')
        CHECK_CONTAINS(text, nl // '    maxwell_fraction = 0.25, 0.125, 0.0625' // nl, 'the branches only')
        CHECK_CONTAINS(text, nl // '    maxwell_tau_G = 0.001, 0.75, 20.0' // nl, 'tau_G default')
        CHECK_CONTAINS(text, nl // "    kind = 'tendon'" // nl, 'actuator kind in lower case')
        CHECK_CONTAINS(text, nl // '    offset = 0.001, -0.0025' // nl, 'offset')
        CHECK_EQUAL(occurrences(text, 'tension'), 1, 'no tension for the pneumatic chamber')
        CHECK_EQUAL(occurrences(text, 'pressure'), 1, 'no pressure for the tendon')
        CHECK_EQUAL(occurrences(text, 'maxwell'), 3, 'no Maxwell variables for the elastic rod')
        CHECK_EQUAL(occurrences(text, '%'), 0, 'no component prefixes')
    end subroutine test_resolved_text_form

    integer function occurrences(text, fragment) result(n)
        character(len=*), intent(in) :: text, fragment
        integer :: at, from
        n = 0
        from = 1
        do
            at = index(text(from:), fragment)
            if (at == 0) exit
            n = n + 1
            from = from + at
        end do
    end function occurrences

    ! Directions and d1 off the axes: the resolved (normalized) vectors must read back to the
    ! same bits, i.e. resolving an already resolved rod must not change it.
    subroutine test_round_trip_oblique_directors()
        call check_round_trip('&time t_end = 1, dt = 0.5 /' // nl // &
            '&rod n_elements = 1, length = 1, direction = 1, 2, 3, EA = 1, GA1 = 1, GA2 = 1,' // &
            ' EI1 = 1, EI2 = 1, GJ = 1, rhoA = 1, rhoI1 = 1, rhoI2 = 1 /' // nl // &
            '&rod n_elements = 1, length = 1, direction = 0.3, -0.7, 0.2, d1 = 1, 1, 1,' // &
            ' EA = 1, GA1 = 1, GA2 = 1, EI1 = 1, EI2 = 1, GJ = 1, rhoA = 1, rhoI1 = 1,' // &
            ' rhoI2 = 1 /' // nl, &
            'oblique.nml')
    end subroutine test_round_trip_oblique_directors

    ! A helix with oblique axis, an initial rigid motion and units; a polyline of capacity points
    ! whose derived start, direction and length (and the helix's length) must read back to the
    ! same bits, being compared with the given ones on the second read.
    subroutine test_round_trip_curved_rods()
        character(len=:), allocatable :: points
        integer :: k
        points = ''
        do k = 1, max_polyline_points
            points = points // str(cos(0.3_rk * k) / 3.0_rk) // ', ' // str(sin(0.3_rk * k) / 7.0_rk) // &
                ', ' // str(0.1_rk * k) // ', '
        end do
        call check_round_trip("&run units = 'mm_kg_ms' /" // nl // '&time t_end = 1, dt = 0.5 /' // nl // &
            "&rod n_elements = 5, geometry = 'helix', start = 0.1, -0.2, 0.3, direction = 1, 2, 3," // nl // &
            '     helix_radius = 0.3, helix_pitch = -0.07, helix_turns = 2.25, d1 = 1, 1, 0,' // nl // &
            '     velocity = 0.1, 0.2, 0.3, angular_velocity = 1, -2, 3, rotation_center = 1, 1, 1,' // nl // &
            '     EA = 1, GA1 = 1, GA2 = 1, EI1 = 1, EI2 = 1, GJ = 1, rhoA = 1, rhoI1 = 1, rhoI2 = 1 /' // nl // &
            "&rod n_elements = 7, geometry = 'polyline', points = " // points // nl // &
            '     EA = 1, GA1 = 1, GA2 = 1, EI1 = 1, EI2 = 1, GJ = 1, rhoA = 1, rhoI1 = 1, rhoI2 = 1 /' // nl, &
            'curved.nml')
    end subroutine test_round_trip_curved_rods

    !> A bundle (issue 10): a core and a helical wire with a phase, a revolute joint with an
    !> oblique axis, a fixed plate and a driven one (a table), and &contact with given margin
    !> and self_contact; the wire's contact_radius given, the core's derived from its circle.
    function bundle() result(text)
        character(len=:), allocatable :: text
        text = '&time t_end = 1, dt = 0.25 /' // nl // &
            "&rod name = 'core', n_elements = 6, length = 0.3, direction = 0, 0, 1," // nl // &
            "     section = 'circle', radius = 1e-3, E = 2e11, nu = 0.3, density = 7800 /" // nl // &
            "&rod name = 'wire', n_elements = 5, geometry = 'helix', direction = 0, 0, 1," // nl // &
            '     start = 1e-3, 1.7320508075688772e-3, 0, helix_radius = 2e-3,' // nl // &
            '     helix_phase = 1.0471975511965976, helix_pitch = 0.1, helix_turns = 3,' // nl // &
            "     contact_radius = 1.1e-3, section = 'circle', radius = 1e-3, E = 2e11, nu = 0.3," // nl // &
            '     density = 7800 /' // nl // &
            "&rod name = 'tail', n_elements = 2, length = 0.1, start = 0, 0, 0.3, direction = 1, 1, 1," // nl // &
            "     section = 'tube', radius = 1e-3, inner_radius = 5e-4, E = 2e11, nu = 0.3," // nl // &
            '     density = 7800 /' // nl // &
            "&joint rod_a = 'core', end_a = 'end', rod_b = 'tail', end_b = 'start'," // nl // &
            "       kind = 'revolute', axis = 0.1, -0.7, 0.3 /" // nl // &
            "&plate name = 'base', rods = 'core', 'wire', end = 'start' /" // nl // &
            "&plate name = 'head', rods = 'wire', end = 'end', centre = 0, 0, 0.3," // nl // &
            '       displacement = 0, 0, 1e-4, rotation = 0, 0, 0.05, time_function = ''table'',' // nl // &
            '       table_times = 0, 0.5, 1, table_values = 0, 1, 0.3333333333333333 /' // nl // &
            '&contact stiffness = 1.5e12, margin = 2e-4, self_contact = .false.,' // nl // &
            '         points_per_element = 6, mu = 0.15, slip_velocity = 2e-5 /' // nl
    end function bundle

    ! The bundle round-trips (derived plate centre, contact radius, skip, normalized axis and the
    ! helix's phase read back to the same bits).
    subroutine test_round_trip_bundle()
        call check_round_trip(bundle(), 'bundle.nml')
    end subroutine test_round_trip_bundle

    ! The form of the bundle groups: one block per plate, its rods without the unused places,
    ! &contact after the plates; helix_phase only for the helix (straight rods leave it out);
    ! without &contact no &contact block and no contact_radius.
    subroutine test_bundle_text_form()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        call parse_scene(bundle(), 'bundle.nml', scene, errors)
        CHECK_EQUAL(errors%count, 0, 'valid bundle: ' // errors%joined())
        text = resolved_scene_text(scene)
        CHECK_EQUAL(occurrences(text, nl // '&plate' // nl), 2, 'one &plate block per plate')
        CHECK_EQUAL(occurrences(text, nl // '&contact' // nl), 1, 'one &contact block')
        CHECK_CONTAINS(text, nl // "    rods = 'core', 'wire'" // nl, 'plate rods, given places only')
        CHECK_CONTAINS(text, nl // "    rods = 'wire'" // nl, 'one rod')
        CHECK_EQUAL(occurrences(text, "*''"), 0, 'no repeated blank strings (unused rods)')
        CHECK_EQUAL(occurrences(text, 'helix_phase'), 1, 'helix_phase for the helix only')
        CHECK_CONTAINS(text, nl // '    helix_phase = 1.0471975511965976' // nl, 'the phase')
        CHECK_EQUAL(occurrences(text, 'contact_radius'), 3, 'every rod''s contact radius')
        CHECK_CONTAINS(text, nl // '    self_contact = .false.' // nl, 'self_contact')
        CHECK_CONTAINS(text, nl // '    points_per_element = 6' // nl, 'points_per_element')
        CHECK_TRUE(index(text, '&joint') < index(text, '&plate'), 'joints before plates')
        CHECK_TRUE(index(text, '&plate') < index(text, '&contact'), 'plates before contact')
        CHECK_EQUAL(occurrences(text, 'given'), 0, 'contact%given is not an input variable')
        text = text(1:index(text, '&contact') - 1)
        call parse_scene(text, 'bundle.nml', scene, errors)
        CHECK_EQUAL(errors%count, 3, 'without &contact the three contact radii are refused')
        CHECK_CONTAINS(errors%joined(), "&rod 'wire' contact_radius: 0.0011 given, but", 'wire')
        errors = error_list_t()
        call parse_scene(every_group(), 'every_group.nml', scene, errors)
        text = resolved_scene_text(scene)
        CHECK_EQUAL(occurrences(text, '&contact'), 0, 'no &contact block without contact')
        CHECK_EQUAL(occurrences(text, '&plate'), 0, 'no &plate block without plates')
    end subroutine test_bundle_text_form

    ! A rod whose stiffnesses come from a section, E, nu and density (as in most scenes of
    ! input/): its resolved text must read back, too.
    subroutine test_round_trip_section_rod()
        call check_round_trip('&time t_end = 1, dt = 0.5 /' // nl // &
            "&rod n_elements = 8, length = 1, section = 'circle', radius = 0.01," // &
            ' E = 2.1e11, nu = 0.3, density = 7800 /' // nl, 'section.nml')
    end subroutine test_round_trip_section_rod

    ! Tables of max_table points whose values need all 17 digits, on a load and an actuator:
    ! every point is written and reads back to the same bits.
    subroutine test_round_trip_full_tables()
        character(len=:), allocatable :: times, values, text
        integer :: k
        times = ''
        values = ''
        do k = 1, max_table
            if (k > 1) times = times // ', '
            if (k > 1) values = values // ', '
            times = times // str(real(k - 1, rk) / 3.0_rk)
            values = values // str(sin(real(k, rk)))
        end do
        text = '&time t_end = 1, dt = 0.5 /' // nl // &
            '&rod n_elements = 1, length = 1, EA = 1, GA1 = 1, GA2 = 1, EI1 = 1, EI2 = 1,' // &
            ' GJ = 1, rhoA = 1, rhoI1 = 1, rhoI2 = 1 /' // nl // &
            "&load rod = 'rod1', where = 'end', force = 1, 0, 0, time_function = 'table'," // nl // &
            '      table_times = ' // times // ',' // nl // &
            '      table_values = ' // values // ' /' // nl // &
            "&actuator rod = 'rod1', kind = 'tendon', offset = 0, 0, tension = 1," // nl // &
            "      time_function = 'table', table_times = " // times // ',' // nl // &
            '      table_values = ' // values // ' /' // nl
        call check_round_trip(text, 'full_tables.nml')
    end subroutine test_round_trip_full_tables

    ! ---- field-by-field comparison ---------------------------------------------------------

    !> Same bits (so -0.0 /= 0.0 and every last digit counts).
    elemental logical function same(a, b)
        real(rk), intent(in) :: a, b
        same = transfer(a, 1_i8) == transfer(b, 1_i8)
    end function same

    subroutine check_real(a, b, what)
        real(rk), intent(in) :: a, b
        character(len=*), intent(in) :: what
        CHECK_TRUE(same(a, b), what // ' bitwise equal')
    end subroutine check_real

    subroutine check_reals(a, b, what)
        real(rk), intent(in) :: a(:), b(:)
        character(len=*), intent(in) :: what
        CHECK_EQUAL(size(a), size(b), what // ' size')
        if (size(a) == size(b)) then
            CHECK_TRUE(all(same(a, b)), what // ' bitwise equal')
        end if
    end subroutine check_reals

    subroutine check_same_scene(a, b)
        type(scene_t), intent(in) :: a, b
        integer :: i
        CHECK_EQUAL(b%run%title, a%run%title, 'run%title')
        CHECK_EQUAL(b%run%formulation_default, a%run%formulation_default, 'formulation_default')
        CHECK_EQUAL(b%run%log_level, a%run%log_level, 'run%log_level')
        CHECK_EQUAL(b%run%units, a%run%units, 'run%units')
        call check_real(b%time%t_end, a%time%t_end, 'time%t_end')
        call check_real(b%time%dt, a%time%dt, 'time%dt')
        CHECK_EQUAL(b%time%scheme, a%time%scheme, 'time%scheme')
        CHECK_EQUAL(b%time%quasistatic, a%time%quasistatic, 'time%quasistatic')
        call check_real(b%solver%newton_atol, a%solver%newton_atol, 'solver%newton_atol')
        call check_real(b%solver%newton_rtol, a%solver%newton_rtol, 'solver%newton_rtol')
        CHECK_EQUAL(b%solver%max_newton, a%solver%max_newton, 'solver%max_newton')
        CHECK_EQUAL(b%solver%max_cutbacks, a%solver%max_cutbacks, 'solver%max_cutbacks')
        CHECK_EQUAL(b%solver%petsc_options, a%solver%petsc_options, 'solver%petsc_options')
        CHECK_EQUAL(b%output%path, a%output%path, 'output%path')
        CHECK_EQUAL(b%output%stride, a%output%stride, 'output%stride')
        CHECK_EQUAL(b%output%fields, a%output%fields, 'output%fields')
        CHECK_EQUAL(b%output%flush_every, a%output%flush_every, 'output%flush_every')
        CHECK_EQUAL(b%output%xdmf, a%output%xdmf, 'output%xdmf')
        CHECK_EQUAL(size(b%rods), size(a%rods), 'number of rods')
        CHECK_EQUAL(size(b%bcs), size(a%bcs), 'number of bcs')
        CHECK_EQUAL(size(b%loads), size(a%loads), 'number of loads')
        CHECK_EQUAL(size(b%actuators), size(a%actuators), 'number of actuators')
        CHECK_EQUAL(size(b%joints), size(a%joints), 'number of joints')
        CHECK_EQUAL(size(b%plates), size(a%plates), 'number of plates')
        call check_same_contact(a%contact, b%contact)
        if (size(b%rods) /= size(a%rods) .or. size(b%bcs) /= size(a%bcs) .or. &
            size(b%loads) /= size(a%loads) .or. size(b%actuators) /= size(a%actuators) .or. &
            size(b%joints) /= size(a%joints) .or. size(b%plates) /= size(a%plates)) return
        do i = 1, size(a%rods)
            call check_same_rod(a%rods(i), b%rods(i))
        end do
        do i = 1, size(a%bcs)
            call check_same_bc(a%bcs(i), b%bcs(i))
        end do
        do i = 1, size(a%loads)
            call check_same_load(a%loads(i), b%loads(i))
        end do
        do i = 1, size(a%actuators)
            call check_same_actuator(a%actuators(i), b%actuators(i))
        end do
        do i = 1, size(a%joints)
            call check_same_joint(a%joints(i), b%joints(i))
        end do
        do i = 1, size(a%plates)
            call check_same_plate(a%plates(i), b%plates(i))
        end do
    end subroutine check_same_scene

    ! input_line is where the group stood in its file, not an input variable: not compared.
    subroutine check_same_rod(a, b)
        type(rod_input_t), intent(in) :: a, b
        character(len=:), allocatable :: r
        r = 'rod ' // trim(a%name) // ': '
        CHECK_EQUAL(b%name, a%name, r // 'name')
        CHECK_EQUAL(b%formulation, a%formulation, r // 'formulation')
        CHECK_EQUAL(b%n_elements, a%n_elements, r // 'n_elements')
        CHECK_EQUAL(b%degree, a%degree, r // 'degree')
        CHECK_EQUAL(b%n_gauss, a%n_gauss, r // 'n_gauss')
        call check_reals(b%start, a%start, r // 'start')
        call check_reals(b%direction, a%direction, r // 'direction')
        call check_reals(b%d1, a%d1, r // 'd1')
        call check_real(b%length, a%length, r // 'length')
        CHECK_EQUAL(b%geometry, a%geometry, r // 'geometry')
        call check_real(b%helix_radius, a%helix_radius, r // 'helix_radius')
        call check_real(b%helix_pitch, a%helix_pitch, r // 'helix_pitch')
        call check_real(b%helix_turns, a%helix_turns, r // 'helix_turns')
        call check_reals(b%points, a%points, r // 'points')
        call check_reals(b%velocity, a%velocity, r // 'velocity')
        call check_reals(b%angular_velocity, a%angular_velocity, r // 'angular_velocity')
        call check_reals(b%rotation_center, a%rotation_center, r // 'rotation_center')
        CHECK_EQUAL(b%section, a%section, r // 'section')
        call check_real(b%radius, a%radius, r // 'radius')
        call check_real(b%inner_radius, a%inner_radius, r // 'inner_radius')
        call check_real(b%width, a%width, r // 'width')
        call check_real(b%height, a%height, r // 'height')
        call check_real(b%E, a%E, r // 'E')
        call check_real(b%G, a%G, r // 'G')
        call check_real(b%nu, a%nu, r // 'nu')
        call check_real(b%density, a%density, r // 'density')
        call check_real(b%EA, a%EA, r // 'EA')
        call check_real(b%GA1, a%GA1, r // 'GA1')
        call check_real(b%GA2, a%GA2, r // 'GA2')
        call check_real(b%EI1, a%EI1, r // 'EI1')
        call check_real(b%EI2, a%EI2, r // 'EI2')
        call check_real(b%GJ, a%GJ, r // 'GJ')
        call check_real(b%rhoA, a%rhoA, r // 'rhoA')
        call check_real(b%rhoI1, a%rhoI1, r // 'rhoI1')
        call check_real(b%rhoI2, a%rhoI2, r // 'rhoI2')
        call check_real(b%shear_factor, a%shear_factor, r // 'shear_factor')
        CHECK_EQUAL(b%torsion_constant, a%torsion_constant, r // 'torsion_constant')
        CHECK_EQUAL(b%prestressed, a%prestressed, r // 'prestressed')
        CHECK_EQUAL(b%constraint, a%constraint, r // 'constraint')
        call check_reals(b%maxwell_fraction, a%maxwell_fraction, r // 'maxwell_fraction')
        call check_reals(b%maxwell_tau_E, a%maxwell_tau_E, r // 'maxwell_tau_E')
        call check_reals(b%maxwell_tau_G, a%maxwell_tau_G, r // 'maxwell_tau_G')
        CHECK_EQUAL(b%em_variant, a%em_variant, r // 'em_variant')
        call check_real(b%contact_radius, a%contact_radius, r // 'contact_radius')
        call check_real(b%helix_phase, a%helix_phase, r // 'helix_phase')
    end subroutine check_same_rod

    subroutine check_same_bc(a, b)
        type(bc_input_t), intent(in) :: a, b
        CHECK_EQUAL(b%rod, a%rod, 'bc rod')
        CHECK_EQUAL(b%end, a%end, 'bc end')
        CHECK_EQUAL(b%kind, a%kind, 'bc kind')
        call check_reals(b%displacement, a%displacement, 'bc displacement')
        call check_reals(b%rotation, a%rotation, 'bc rotation')
        CHECK_EQUAL(b%time_function, a%time_function, 'bc time_function')
        call check_real(b%t_on, a%t_on, 'bc t_on')
        call check_real(b%t_off, a%t_off, 'bc t_off')
        call check_reals(b%table_times, a%table_times, 'bc table_times')
        call check_reals(b%table_values, a%table_values, 'bc table_values')
        call check_real(b%mass, a%mass, 'bc mass')
        call check_reals(b%centre, a%centre, 'bc centre')
        call check_reals(b%inertia, a%inertia, 'bc inertia')
        call check_reals(b%inertia_products, a%inertia_products, 'bc inertia_products')
    end subroutine check_same_bc

    subroutine check_same_load(a, b)
        type(load_input_t), intent(in) :: a, b
        CHECK_EQUAL(b%rod, a%rod, 'load rod')
        CHECK_EQUAL(b%where, a%where, 'load where')
        call check_reals(b%force, a%force, 'load force')
        call check_reals(b%moment, a%moment, 'load moment')
        call check_reals(b%acceleration, a%acceleration, 'load acceleration')
        CHECK_EQUAL(b%frame, a%frame, 'load frame')
        CHECK_EQUAL(b%time_function, a%time_function, 'load time_function')
        call check_real(b%t_on, a%t_on, 'load t_on')
        call check_real(b%t_off, a%t_off, 'load t_off')
        call check_reals(b%table_times, a%table_times, 'load table_times')
        call check_reals(b%table_values, a%table_values, 'load table_values')
    end subroutine check_same_load

    subroutine check_same_actuator(a, b)
        type(actuator_input_t), intent(in) :: a, b
        CHECK_EQUAL(b%rod, a%rod, 'actuator rod')
        CHECK_EQUAL(b%kind, a%kind, 'actuator kind')
        call check_reals(b%offset, a%offset, 'actuator offset')
        call check_real(b%area, a%area, 'actuator area')
        call check_real(b%pressure, a%pressure, 'actuator pressure')
        call check_real(b%tension, a%tension, 'actuator tension')
        CHECK_EQUAL(b%time_function, a%time_function, 'actuator time_function')
        call check_real(b%t_on, a%t_on, 'actuator t_on')
        call check_real(b%t_off, a%t_off, 'actuator t_off')
        call check_reals(b%table_times, a%table_times, 'actuator table_times')
        call check_reals(b%table_values, a%table_values, 'actuator table_values')
    end subroutine check_same_actuator

    subroutine check_same_joint(a, b)
        type(joint_input_t), intent(in) :: a, b
        CHECK_EQUAL(b%rod_a, a%rod_a, 'joint rod_a')
        CHECK_EQUAL(b%end_a, a%end_a, 'joint end_a')
        CHECK_EQUAL(b%rod_b, a%rod_b, 'joint rod_b')
        CHECK_EQUAL(b%end_b, a%end_b, 'joint end_b')
        CHECK_EQUAL(b%kind, a%kind, 'joint kind')
        call check_reals(b%axis, a%axis, 'joint axis')
    end subroutine check_same_joint

    subroutine check_same_plate(a, b)
        type(plate_input_t), intent(in) :: a, b
        integer :: k
        CHECK_EQUAL(b%name, a%name, 'plate name')
        do k = 1, size(a%rods)
            CHECK_EQUAL(b%rods(k), a%rods(k), 'plate rods')
        end do
        CHECK_EQUAL(b%end, a%end, 'plate end')
        call check_reals(b%centre, a%centre, 'plate centre')
        call check_reals(b%displacement, a%displacement, 'plate displacement')
        call check_reals(b%rotation, a%rotation, 'plate rotation')
        CHECK_EQUAL(b%time_function, a%time_function, 'plate time_function')
        call check_real(b%t_on, a%t_on, 'plate t_on')
        call check_real(b%t_off, a%t_off, 'plate t_off')
        call check_reals(b%table_times, a%table_times, 'plate table_times')
        call check_reals(b%table_values, a%table_values, 'plate table_values')
    end subroutine check_same_plate

    subroutine check_same_contact(a, b)
        type(contact_input_t), intent(in) :: a, b
        CHECK_EQUAL(b%given, a%given, 'contact given')
        call check_real(b%stiffness, a%stiffness, 'contact stiffness')
        call check_real(b%margin, a%margin, 'contact margin')
        CHECK_EQUAL(b%skip, a%skip, 'contact skip')
        CHECK_EQUAL(b%points_per_element, a%points_per_element, 'contact points_per_element')
        CHECK_EQUAL(b%self_contact, a%self_contact, 'contact self_contact')
        call check_real(b%mu, a%mu, 'contact mu')
        call check_real(b%slip_velocity, a%slip_velocity, 'contact slip_velocity')
    end subroutine check_same_contact

end module rs_test_io_scene_writer

!> Test program: runs the tests of rs_test_io_scene_writer; exits non-zero if any failed.
program test_scene_writer
    use rs_test_io_scene_writer, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_scene_writer
