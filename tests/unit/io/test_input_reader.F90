#include "rs_assert.h"
!> Unit tests of scene reading (rs_io_input_reader through parse_scene of rs_io_input_file, with
!> rs_io_input_check): values land in their fields, defaults where nothing is given, choices
!> folded to lower case, derived values (direction normalized, default d1, default names and
!> output path, G from nu, stiffnesses and inertias from circle, tube and rectangle sections by
!> hand formulas), the count and text of errors for a few invalid scenes, the variables
!> required or allowed only under a condition (geometry), and that the example of every variable
!> in the input reference reads; string arrays (&plate rods) and the &contact flag. The
!> malformed scenes of tests/input/bad/ are not repeated here.
module rs_test_io_input_reader
    use rs_core_kinds, only: rk, pi
    use rs_core_error, only: error_list_t
    use rs_test_assert, only: run_test, assert_true, assert_equal, assert_contains, assert_close
    use rs_model_scene, only: scene_t, unset_real
    use rs_io_input_file, only: parse_scene
    use rs_io_input_reader, only: read_scene_text
    use rs_io_input_spec, only: group_spec_t, input_groups, split_condition
    implicit none
    private

    public :: run_all_tests

    character(len=*), parameter :: nl = new_line('a')
    real(rk), parameter :: tight = 1.0e-14_rk

    !> Rod stiffnesses given directly (section = 'none'), for scenes that need a valid rod.
    character(len=*), parameter :: direct = 'EA = 1e4, GA1 = 2e3, GA2 = 3e3, EI1 = 12.5, ' // &
        'EI2 = 13.5, GJ = 7, rhoA = 0.5, rhoI1 = 1e-3, rhoI2 = 2e-3'

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('values_land_in_fields', test_values_land_in_fields)
        call run_test('defaults', test_defaults)
        call run_test('choices_folded_to_lower_case', test_choices_folded_to_lower_case)
        call run_test('formulation_default', test_formulation_default)
        call run_test('direction_and_default_d1', test_direction_and_default_d1)
        call run_test('given_d1_made_orthonormal', test_given_d1_made_orthonormal)
        call run_test('subscripts_and_repeat_counts', test_subscripts_and_repeat_counts)
        call run_test('default_rod_names', test_default_rod_names)
        call run_test('default_output_path', test_default_output_path)
        call run_test('circle_derived_values', test_circle_derived_values)
        call run_test('tube_derived_values', test_tube_derived_values)
        call run_test('rectangle_torsion_constants', test_rectangle_torsion_constants)
        call run_test('g_given_wins_over_nu', test_g_given_wins_over_nu)
        call run_test('resolve_errors_all_reported', test_resolve_errors_all_reported)
        call run_test('read_errors_skip_cross_checks', test_read_errors_skip_cross_checks)
        call run_test('section_errors', test_section_errors)
        call run_test('every_example_reads', test_every_example_reads)
        call run_test('conditional_variables', test_conditional_variables)
        call run_test('string_arrays', test_string_arrays)
    end subroutine run_all_tests

    !> Parse `text` as file `file` and check that it has exactly `n_errors` errors; on a
    !> mismatch the errors are shown.
    subroutine parse(text, scene, errors, n_errors, file)
        character(len=*), intent(in) :: text
        type(scene_t), intent(out) :: scene
        type(error_list_t), intent(out) :: errors
        integer, intent(in) :: n_errors
        character(len=*), intent(in), optional :: file
        if (present(file)) then
            call parse_scene(text, file, scene, errors)
        else
            call parse_scene(text, 'cases/two_rods.nml', scene, errors)
        end if
        CHECK_EQUAL(errors%count, n_errors, 'number of errors; errors: ' // errors%joined())
    end subroutine parse

    !> Check that the scene has `n` rods, bcs and loads.
    logical function has_sizes(scene, n_rods, n_bcs, n_loads) result(ok)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: n_rods, n_bcs, n_loads
        ok = allocated(scene%rods) .and. allocated(scene%bcs) .and. allocated(scene%loads)
        CHECK_TRUE(ok, 'arrays allocated')
        if (.not. ok) return
        CHECK_EQUAL(size(scene%rods), n_rods, 'number of rods')
        CHECK_EQUAL(size(scene%bcs), n_bcs, 'number of bcs')
        CHECK_EQUAL(size(scene%loads), n_loads, 'number of loads')
        ok = size(scene%rods) == n_rods .and. size(scene%bcs) == n_bcs .and. &
            size(scene%loads) == n_loads
    end function has_sizes

    !> A valid scene with two rods (a circle section and direct stiffnesses), a bc and a load.
    function two_rods() result(text)
        character(len=:), allocatable :: text
        text = "&run title = 'Two Rods' /" // nl // &                                   ! 1
            '&time t_end = 2.0, dt = 0.05 /' // nl // &                                ! 2
            '&rod' // nl // &                                                          ! 3
            "    name = 'beam', n_elements = 8" // nl // &                             ! 4
            '    direction = 3, 0, 4' // nl // &                                       ! 5
            '    length = 2.0' // nl // &                                              ! 6
            "    section = 'Circle', radius = 0.02" // nl // &                         ! 7
            '    E = 2.0e11, nu = 0.25, density = 7850, shear_factor = 0.9' // nl // & ! 8
            '/' // nl // &                                                             ! 9
            '&rod n_elements = 4, degree = 1, length = 0.5, direction = 0, 0, 2' // nl // &
            '     start = 1.0, 2.0, 3.0' // nl // &
            '     ' // direct // ' /' // nl // &
            "&bc rod = 'beam', end = 'START', kind = 'Clamped' /" // nl // &
            "&load rod = 'rod2', where = 'end', force = 0, 0, -100, frame = 'Follower'," // nl // &
            "      time_function = 'ramp', t_off = 1 /" // nl
    end function two_rods

    subroutine test_values_land_in_fields()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        real(rk), parameter :: start(3) = [1.0_rk, 2.0_rk, 3.0_rk]
        real(rk), parameter :: force(3) = [0.0_rk, 0.0_rk, -100.0_rk]
        call parse(two_rods(), scene, errors, 0)
        CHECK_EQUAL(scene%source_file, 'cases/two_rods.nml', 'source file kept')
        CHECK_EQUAL(scene%source_text, two_rods(), 'source text kept verbatim')
        CHECK_EQUAL(trim(scene%run%title), 'Two Rods', 'title: case kept (no allowed list)')
        CHECK_CLOSE(scene%time%t_end, 2.0_rk, 0.0_rk, 0.0_rk, 't_end')
        CHECK_CLOSE(scene%time%dt, 0.05_rk, 0.0_rk, 0.0_rk, 'dt')
        if (.not. has_sizes(scene, 2, 1, 1)) return
        CHECK_EQUAL(trim(scene%rods(1)%name), 'beam', 'name of rod 1')
        CHECK_EQUAL(scene%rods(1)%input_line, 3, 'line of rod 1')
        CHECK_EQUAL(scene%rods(2)%input_line, 10, 'line of rod 2')
        CHECK_EQUAL(scene%rods(1)%n_elements, 8, 'rods(1)%n_elements')
        CHECK_CLOSE(scene%rods(1)%length, 2.0_rk, 0.0_rk, 0.0_rk, 'rods(1)%length')
        CHECK_CLOSE(scene%rods(1)%radius, 0.02_rk, 0.0_rk, 0.0_rk, 'rods(1)%radius')
        CHECK_CLOSE(scene%rods(1)%shear_factor, 0.9_rk, 0.0_rk, 0.0_rk, 'rods(1)%shear_factor')
        CHECK_EQUAL(scene%rods(2)%n_elements, 4, 'rods(2)%n_elements')
        CHECK_EQUAL(scene%rods(2)%degree, 1, 'rods(2)%degree')
        CHECK_CLOSE(scene%rods(2)%length, 0.5_rk, 0.0_rk, 0.0_rk, 'rods(2)%length')
        CHECK_CLOSE(scene%rods(2)%start, start, 0.0_rk, 0.0_rk, 'rods(2)%start')
        CHECK_CLOSE(scene%rods(2)%EA, 1.0e4_rk, 0.0_rk, 0.0_rk, 'rods(2)%EA')
        CHECK_CLOSE(scene%rods(2)%GA1, 2.0e3_rk, 0.0_rk, 0.0_rk, 'rods(2)%GA1')
        CHECK_CLOSE(scene%rods(2)%GA2, 3.0e3_rk, 0.0_rk, 0.0_rk, 'rods(2)%GA2')
        CHECK_CLOSE(scene%rods(2)%EI1, 12.5_rk, 0.0_rk, 0.0_rk, 'rods(2)%EI1')
        CHECK_CLOSE(scene%rods(2)%EI2, 13.5_rk, 0.0_rk, 0.0_rk, 'rods(2)%EI2')
        CHECK_CLOSE(scene%rods(2)%GJ, 7.0_rk, 0.0_rk, 0.0_rk, 'rods(2)%GJ')
        CHECK_CLOSE(scene%rods(2)%rhoA, 0.5_rk, 0.0_rk, 0.0_rk, 'rods(2)%rhoA')
        CHECK_CLOSE(scene%rods(2)%rhoI1, 1.0e-3_rk, 0.0_rk, 0.0_rk, 'rods(2)%rhoI1')
        CHECK_CLOSE(scene%rods(2)%rhoI2, 2.0e-3_rk, 0.0_rk, 0.0_rk, 'rods(2)%rhoI2')
        CHECK_EQUAL(trim(scene%bcs(1)%rod), 'beam', 'bc rod')
        CHECK_EQUAL(scene%bcs(1)%input_line, 13, 'line of the bc')
        CHECK_EQUAL(trim(scene%loads(1)%rod), 'rod2', 'load rod')
        CHECK_EQUAL(trim(scene%loads(1)%where), 'end', 'load where')
        CHECK_CLOSE(scene%loads(1)%force, force, 0.0_rk, 0.0_rk, 'load force')
        CHECK_EQUAL(trim(scene%loads(1)%time_function), 'ramp', 'time function')
        CHECK_CLOSE(scene%loads(1)%t_off, 1.0_rk, 0.0_rk, 0.0_rk, 't_off')
    end subroutine test_values_land_in_fields

    ! The defaults of docs/user/input.md (DESIGN.md 6) where a scene says nothing.
    subroutine test_defaults()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        real(rk), parameter :: zero(3) = 0.0_rk
        call parse(two_rods(), scene, errors, 0)
        CHECK_EQUAL(trim(scene%run%formulation_default), 'ph_director', 'formulation_default')
        CHECK_EQUAL(trim(scene%run%log_level), 'info', 'log_level')
        CHECK_EQUAL(trim(scene%time%scheme), 'midpoint', 'scheme')
        CHECK_EQUAL(scene%time%quasistatic, .false., 'quasistatic')
        CHECK_CLOSE(scene%solver%newton_atol, 1.0e-10_rk, 0.0_rk, 0.0_rk, 'newton_atol')
        CHECK_CLOSE(scene%solver%newton_rtol, 0.0_rk, 0.0_rk, 0.0_rk, 'newton_rtol')
        CHECK_EQUAL(scene%solver%max_newton, 25, 'max_newton')
        CHECK_EQUAL(scene%solver%max_cutbacks, 6, 'max_cutbacks')
        CHECK_EQUAL(trim(scene%solver%petsc_options), '', 'petsc_options')
        CHECK_EQUAL(scene%output%stride, 1, 'stride')
        CHECK_EQUAL(trim(scene%output%fields), 'all', 'fields')
        CHECK_EQUAL(scene%output%flush_every, 10, 'flush_every')
        CHECK_EQUAL(scene%output%xdmf, .true., 'xdmf')
        if (.not. has_sizes(scene, 2, 1, 1)) return
        CHECK_EQUAL(scene%rods(1)%degree, 2, 'degree')
        CHECK_EQUAL(scene%rods(1)%n_gauss, 2, 'n_gauss')
        CHECK_CLOSE(scene%rods(1)%start, zero, 0.0_rk, 0.0_rk, 'start')
        CHECK_TRUE(scene%rods(2)%shear_factor == unset_real, 'shear_factor: unset without a section')
        CHECK_EQUAL(trim(scene%rods(1)%constraint), 'none', 'constraint')
        CHECK_EQUAL(scene%rods(1)%prestressed, .false., 'prestressed')
        CHECK_EQUAL(trim(scene%rods(1)%torsion_constant), 'polar', 'torsion_constant of a circle')
        CHECK_EQUAL(trim(scene%rods(2)%torsion_constant), '', 'torsion_constant (none): unset, GJ is given')
        CHECK_EQUAL(trim(scene%rods(2)%section), 'none', 'section')
        CHECK_TRUE(scene%rods(2)%E == unset_real, 'E stays unset without a section')
        CHECK_CLOSE(scene%loads(1)%moment, zero, 0.0_rk, 0.0_rk, 'moment')
        CHECK_CLOSE(scene%loads(1)%acceleration, zero, 0.0_rk, 0.0_rk, 'acceleration')
        CHECK_CLOSE(scene%loads(1)%t_on, 0.0_rk, 0.0_rk, 0.0_rk, 't_on')
        CHECK_TRUE(all(scene%loads(1)%table_times == unset_real), 'no table')
        CHECK_TRUE(all(scene%rods(1)%maxwell_fraction == unset_real), 'no Maxwell branches')
        CHECK_TRUE(all(scene%rods(2)%maxwell_tau_G == unset_real), 'no Maxwell relaxation times')
        CHECK_TRUE(allocated(scene%actuators), 'actuators allocated')
        if (allocated(scene%actuators)) then
            CHECK_EQUAL(size(scene%actuators), 0, 'no actuators')
        end if
    end subroutine test_defaults

    ! Choices are matched without case and stored in lower case; group and variable names too.
    subroutine test_choices_folded_to_lower_case()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        call parse(two_rods(), scene, errors, 0)
        if (.not. has_sizes(scene, 2, 1, 1)) return
        CHECK_EQUAL(trim(scene%rods(1)%section), 'circle', "'Circle'")
        CHECK_EQUAL(trim(scene%bcs(1)%end), 'start', "'START'")
        CHECK_EQUAL(trim(scene%bcs(1)%kind), 'clamped', "'Clamped'")
        CHECK_EQUAL(trim(scene%loads(1)%frame), 'follower', "'Follower'")
        text = '&TIME T_End = 1, DT = 0.5, Scheme = "MidPoint" /' // nl // &
            "&Rod N_Elements = 2, LENGTH = 3, Constraint = 'Kirchhoff', " // direct // ' /' // nl
        call parse(text, scene, errors, 0)
        if (.not. has_sizes(scene, 1, 0, 0)) return
        CHECK_CLOSE(scene%time%t_end, 1.0_rk, 0.0_rk, 0.0_rk, 'T_End')
        CHECK_EQUAL(trim(scene%time%scheme), 'midpoint', 'double-quoted choice')
        CHECK_EQUAL(scene%rods(1)%n_elements, 2, 'N_Elements')
        CHECK_EQUAL(trim(scene%rods(1)%constraint), 'kirchhoff', 'constraint')
    end subroutine test_choices_folded_to_lower_case

    subroutine test_formulation_default()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        text = "&run formulation_default = 'SE3_PG' /" // nl // &
            '&time t_end = 1, dt = 0.5 /' // nl // &
            '&rod n_elements = 2, length = 1, ' // direct // ' /' // nl // &
            "&rod n_elements = 2, length = 1, formulation = 'ph_planar', " // direct // ' /' // nl
        call parse(text, scene, errors, 0)
        CHECK_EQUAL(trim(scene%run%formulation_default), 'se3_pg', 'folded')
        if (.not. has_sizes(scene, 2, 0, 0)) return
        CHECK_EQUAL(trim(scene%rods(1)%formulation), 'se3_pg', 'from formulation_default')
        CHECK_EQUAL(trim(scene%rods(2)%formulation), 'ph_planar', 'given formulation kept')
    end subroutine test_formulation_default

    ! direction = (3, 0, 4) -> (0.6, 0, 0.8); default d1 = e_z x t normalized = e_y; for a
    ! rod along e_z, d1 = e_x. Both are unit vectors normal to the tangent.
    subroutine test_direction_and_default_d1()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        real(rk), parameter :: t1(3) = [0.6_rk, 0.0_rk, 0.8_rk], e_x(3) = [1.0_rk, 0.0_rk, 0.0_rk]
        real(rk), parameter :: e_y(3) = [0.0_rk, 1.0_rk, 0.0_rk], e_z(3) = [0.0_rk, 0.0_rk, 1.0_rk]
        real(rk), parameter :: given(3) = [-1.0_rk, 2.0_rk, -0.5_rk]
        real(rk) :: t(3), d1(3)
        character(len=:), allocatable :: text
        call parse(two_rods(), scene, errors, 0)
        if (.not. has_sizes(scene, 2, 1, 1)) return
        CHECK_CLOSE(scene%rods(1)%direction, t1, 1.0e-16_rk, 0.0_rk, 'direction normalized')
        CHECK_CLOSE(scene%rods(1)%d1, e_y, 1.0e-16_rk, 0.0_rk, 'd1 of the (3, 0, 4) rod')
        CHECK_CLOSE(scene%rods(2)%direction, e_z, 0.0_rk, 0.0_rk, '(0, 0, 2) normalized')
        CHECK_CLOSE(scene%rods(2)%d1, e_x, 0.0_rk, 0.0_rk, 'd1 of a rod along e_z')
        text = '&time t_end = 1, dt = 0.5 /' // nl // &
            '&rod n_elements = 2, length = 1, direction = -1, 2, -0.5, ' // direct // ' /' // nl
        call parse(text, scene, errors, 0)
        if (.not. has_sizes(scene, 1, 0, 0)) return
        t = scene%rods(1)%direction
        d1 = scene%rods(1)%d1
        CHECK_CLOSE(t, given / 2.29128784747792_rk, 0.0_rk, 1.0e-14_rk, 'tangent')
        CHECK_CLOSE(norm2(d1), 1.0_rk, 1.0e-15_rk, 0.0_rk, '|d1| = 1')
        CHECK_CLOSE(dot_product(d1, t), 0.0_rk, 1.0e-15_rk, 0.0_rk, 'd1 normal to the tangent')
        CHECK_CLOSE(d1(3), 0.0_rk, 0.0_rk, 0.0_rk, 'd1 horizontal (e_z x t)')
    end subroutine test_direction_and_default_d1

    ! A given d1 loses its component along the tangent and is normalized; its sense is kept.
    subroutine test_given_d1_made_orthonormal()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        real(rk), parameter :: e_y(3) = [0.0_rk, 1.0_rk, 0.0_rk]
        real(rk) :: diagonal(3)
        character(len=:), allocatable :: text
        text = '&time t_end = 1, dt = 0.5 /' // nl // &
            '&rod n_elements = 2, length = 1, d1 = 1, 2, 0, ' // direct // ' /' // nl // &
            '&rod n_elements = 2, length = 1, d1 = 1, -3, 0, ' // direct // ' /' // nl // &
            '&rod n_elements = 2, length = 1, direction = 0, 0, 5, d1 = 1, 1, 1, ' // direct // &
            ' /' // nl
        call parse(text, scene, errors, 0)
        if (.not. has_sizes(scene, 3, 0, 0)) return
        CHECK_CLOSE(scene%rods(1)%d1, e_y, 0.0_rk, 0.0_rk, 'd1 (1, 2, 0) along e_x')
        CHECK_CLOSE(scene%rods(2)%d1, -e_y, 0.0_rk, 0.0_rk, 'd1 (1, -3, 0) keeps its sense')
        diagonal = [1.0_rk, 1.0_rk, 0.0_rk] / sqrt(2.0_rk)
        CHECK_CLOSE(scene%rods(3)%d1, diagonal, 1.0e-16_rk, 0.0_rk, 'd1 (1, 1, 1) along e_z')
    end subroutine test_given_d1_made_orthonormal

    ! start(2) = 5 sets one component; 3*1.0 fills three (DESIGN.md 6: arrays never padded).
    subroutine test_subscripts_and_repeat_counts()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        real(rk), parameter :: start(3) = [0.0_rk, 5.0_rk, 0.0_rk]
        real(rk), parameter :: force(3) = [0.5_rk, 0.5_rk, 1.0_rk]
        real(rk), parameter :: values(3) = [0.0_rk, 0.0_rk, 1.0_rk]
        real(rk) :: diagonal(3)
        character(len=:), allocatable :: text
        text = '&time t_end = 1, dt = 0.5 /' // nl // &
            '&rod n_elements = 2, length = 1, start(2) = 5.0, direction = 3*1.0, ' // direct // &
            ' /' // nl // &
            "&load rod = 'rod1', where = 'end', force = 2*0.5, 1," // nl // &
            "      time_function = 'table'," // nl // &
            '      table_times = 0, 0.5, 1, table_values = 2*0.0, 1 /' // nl
        call parse(text, scene, errors, 0)
        if (.not. has_sizes(scene, 1, 0, 1)) return
        CHECK_CLOSE(scene%rods(1)%start, start, 0.0_rk, 0.0_rk, 'start(2) only')
        diagonal = 1.0_rk / sqrt(3.0_rk)
        CHECK_CLOSE(scene%rods(1)%direction, diagonal, 1.0e-16_rk, 0.0_rk, '3*1.0 normalized')
        CHECK_CLOSE(scene%loads(1)%force, force, 0.0_rk, 0.0_rk, '2*0.5')
        CHECK_CLOSE(scene%loads(1)%table_values(1:3), values, 0.0_rk, 0.0_rk, 'table')
        CHECK_TRUE(scene%loads(1)%table_times(4) == unset_real, 'table not padded')
    end subroutine test_subscripts_and_repeat_counts

    subroutine test_default_rod_names()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        text = '&time t_end = 1, dt = 0.5 /' // nl // &
            '&rod n_elements = 2, length = 1, ' // direct // ' /' // nl // &
            "&rod name = 'arm', n_elements = 2, length = 1, " // direct // ' /' // nl // &
            '&rod n_elements = 2, length = 1, ' // direct // ' /' // nl
        call parse(text, scene, errors, 0)
        if (.not. has_sizes(scene, 3, 0, 0)) return
        CHECK_EQUAL(trim(scene%rods(1)%name), 'rod1', 'first rod')
        CHECK_EQUAL(trim(scene%rods(2)%name), 'arm', 'named rod')
        CHECK_EQUAL(trim(scene%rods(3)%name), 'rod3', 'third rod: its position in the file')
    end subroutine test_default_rod_names

    ! 'out/<scene>.h5' from the file name without directory and last extension.
    subroutine test_default_output_path()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        text = '&time t_end = 1, dt = 0.5 /' // nl // &
            '&rod n_elements = 2, length = 1, ' // direct // ' /' // nl
        call parse(text, scene, errors, 0, file='/data/runs/cantilever.nml')
        CHECK_EQUAL(trim(scene%output%path), 'out/cantilever.h5', 'absolute scene path')
        call parse(text, scene, errors, 0, file='bend.v2.nml')
        CHECK_EQUAL(trim(scene%output%path), 'out/bend.v2.h5', 'only the last extension')
        call parse(text, scene, errors, 0, file='../scene')
        CHECK_EQUAL(trim(scene%output%path), 'out/scene.h5', 'no extension')
        call parse("&output path = 'results/r.h5' /" // nl // text, scene, errors, 0)
        CHECK_EQUAL(trim(scene%output%path), 'results/r.h5', 'given path kept')
    end subroutine test_default_output_path

    ! r = 0.02, E = 2e11, nu = 0.25, density 7850, k = 0.9: G = E / 2.5 = 8e10, A = 4e-4 pi,
    ! I = pi r^4 / 4 = 4e-8 pi, J = 8e-8 pi.
    subroutine test_circle_derived_values()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        call parse(two_rods(), scene, errors, 0)
        if (.not. has_sizes(scene, 2, 1, 1)) return
        associate (rod => scene%rods(1))
            CHECK_CLOSE(rod%G, 8.0e10_rk, 0.0_rk, tight, 'G = E / (2 (1 + nu))')
            CHECK_CLOSE(rod%EA, 8.0e7_rk * pi, 0.0_rk, tight, 'EA = E pi r^2')
            CHECK_CLOSE(rod%GA1, 2.88e7_rk * pi, 0.0_rk, tight, 'GA1 = k G A')
            CHECK_CLOSE(rod%GA2, 2.88e7_rk * pi, 0.0_rk, tight, 'GA2 = k G A')
            CHECK_CLOSE(rod%EI1, 8.0e3_rk * pi, 0.0_rk, tight, 'EI1 = E pi r^4 / 4')
            CHECK_CLOSE(rod%EI2, 8.0e3_rk * pi, 0.0_rk, tight, 'EI2 = EI1')
            CHECK_CLOSE(rod%GJ, 6.4e3_rk * pi, 0.0_rk, tight, 'GJ = G pi r^4 / 2')
            CHECK_CLOSE(rod%rhoA, 3.14_rk * pi, 0.0_rk, tight, 'rhoA = density pi r^2')
            CHECK_CLOSE(rod%rhoI1, 3.14e-4_rk * pi, 0.0_rk, tight, 'rhoI1 = density pi r^4 / 4')
            CHECK_CLOSE(rod%rhoI2, 3.14e-4_rk * pi, 0.0_rk, tight, 'rhoI2 = rhoI1')
        end associate
    end subroutine test_circle_derived_values

    ! Tube R = 0.05, r = 0.04: A = 9e-4 pi, I = pi (R^4 - r^4) / 4 = 9.225e-7 pi.
    subroutine test_tube_derived_values()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        text = '&time t_end = 1, dt = 0.5 /' // nl // &
            "&rod n_elements = 2, length = 1, section = 'tube', radius = 0.05," // &
            ' inner_radius = 0.04, E = 1e9, nu = 0.5, density = 1000 /' // nl
        call parse(text, scene, errors, 0)
        if (.not. has_sizes(scene, 1, 0, 0)) return
        associate (rod => scene%rods(1))
            CHECK_CLOSE(rod%G, 1.0e9_rk / 3.0_rk, 0.0_rk, tight, 'G with nu = 0.5')
            CHECK_CLOSE(rod%EA, 9.0e5_rk * pi, 0.0_rk, tight, 'EA')
            CHECK_CLOSE(rod%EI1, 922.5_rk * pi, 0.0_rk, 1.0e-13_rk, 'EI1')
            CHECK_CLOSE(rod%GJ, 615.0_rk * pi, 0.0_rk, 1.0e-13_rk, 'GJ = G pi (R^4 - r^4) / 2')
            CHECK_CLOSE(rod%rhoA, 0.9_rk * pi, 0.0_rk, tight, 'rhoA')
        end associate
    end subroutine test_tube_derived_values

    ! Rectangle 0.04 x 0.02 (width along d1): I1 = w h^3 / 12, I2 = h w^3 / 12. Square
    ! 0.02 x 0.02 with 'saint_venant': J = 0.140577 a^4 (Timoshenko & Goodier).
    subroutine test_rectangle_torsion_constants()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        text = '&time t_end = 1, dt = 0.5 /' // nl // &
            "&rod n_elements = 2, length = 1, section = 'rectangle', width = 0.04," // &
            " height = 0.02, torsion_constant = 'Polar', E = 1e9, G = 4e8," // &
            ' density = 1000 /' // nl // &
            "&rod n_elements = 2, length = 1, section = 'rectangle', width = 0.02," // &
            " height = 0.02, torsion_constant = 'Saint_Venant', E = 1e9, G = 4e8," // &
            ' density = 1000 /' // nl
        call parse(text, scene, errors, 0)
        if (.not. has_sizes(scene, 2, 0, 0)) return
        CHECK_CLOSE(scene%rods(1)%EI1, 1.0e9_rk * 3.2e-7_rk / 12.0_rk, 0.0_rk, tight, 'EI1')
        CHECK_CLOSE(scene%rods(1)%EI2, 1.0e9_rk * 1.28e-6_rk / 12.0_rk, 0.0_rk, tight, 'EI2')
        CHECK_CLOSE(scene%rods(1)%GJ, 4.0e8_rk * 1.6e-6_rk / 12.0_rk, 0.0_rk, tight, 'GJ polar')
        CHECK_CLOSE(scene%rods(1)%rhoI1, 1000.0_rk * 3.2e-7_rk / 12.0_rk, 0.0_rk, tight, 'rhoI1')
        CHECK_CLOSE(scene%rods(1)%GA1, 4.0e8_rk * 8.0e-4_rk, 0.0_rk, tight, 'GA1 = G A (k = 1)')
        CHECK_EQUAL(trim(scene%rods(2)%torsion_constant), 'saint_venant', 'folded')
        CHECK_CLOSE(scene%rods(2)%GJ, 4.0e8_rk * 0.140577_rk * 1.6e-7_rk, 0.0_rk, 1.0e-5_rk, 'GJ')
    end subroutine test_rectangle_torsion_constants

    subroutine test_g_given_wins_over_nu()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        text = '&time t_end = 1, dt = 0.5 /' // nl // &
            "&rod n_elements = 2, length = 1, section = 'circle', radius = 1," // &
            ' E = 3, G = 1, nu = 0.3, density = 1 /' // nl
        call parse(text, scene, errors, 0)
        if (.not. has_sizes(scene, 1, 0, 0)) return
        CHECK_CLOSE(scene%rods(1)%G, 1.0_rk, 0.0_rk, 0.0_rk, 'G as given')
        CHECK_CLOSE(scene%rods(1)%GJ, pi / 2.0_rk, 0.0_rk, tight, 'GJ from the given G')
    end subroutine test_g_given_wins_over_nu

    ! Every cross-check problem of a scene is reported at once, each with file and line.
    subroutine test_resolve_errors_all_reported()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text, joined, fragment
        text = '&time t_end = 1, dt = 0.5 /' // nl // &                                     ! 1
            "&rod name = 'a', n_elements = 2, length = 1, " // direct // ' /' // nl // &      ! 2
            "&rod name = 'a', n_elements = 2, length = 1, " // direct // ' /' // nl // &      ! 3
            '&rod n_elements = 2, length = 1, direction = 3*0.0, ' // direct // ' /' // nl // & ! 4
            "&load where = 'end', force = 1, 0, 0 /" // nl // &                             ! 5
            "&load rod = 'a', where = 'end', acceleration = 0, 0, 1 /" // nl // &           ! 6
            "&load rod = 'a', where = 'end', time_function = 'hat', t_on = 0.5," // &
            ' t_off = 0.5 /' // nl // &                                                    ! 7
            "&load rod = 'a', where = 'end', time_function = 'table', table_times = 0, 1, 2," // &
            ' table_values = 1, 2 /' // nl                                                 ! 8
        call parse(text, scene, errors, 6, file='x.nml')
        joined = errors%joined()
        fragment = "x.nml:3: &rod name: 'a' is already the name of the rod at line 2"
        CHECK_CONTAINS(joined, fragment, 'duplicate name')
        fragment = "x.nml:4: &rod 'rod3' direction: must not be the zero vector"
        CHECK_CONTAINS(joined, fragment, 'zero direction')
        CHECK_CONTAINS(joined, "x.nml:5: &load rod: required unless where = 'gravity'", 'no rod')
        CHECK_CONTAINS(joined, 'x.nml:6: &load acceleration: only a gravity load takes', 'accel')
        CHECK_CONTAINS(joined, 'x.nml:7: &load t_off: 0.5 must be larger than t_on = 0.5', 't_off')
        CHECK_CONTAINS(joined, 'x.nml:8: &load table_times: a table needs at least 2 times', 'tab')
        CHECK_CONTAINS(joined, '(3 and 2 given)', 'table counts')
    end subroutine test_resolve_errors_all_reported

    ! parse_scene cross-checks only a scene that was read without errors (a read error would
    ! otherwise be repeated as a cross-check error): dt > t_end is not reported here.
    subroutine test_read_errors_skip_cross_checks()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text
        text = '&time t_end = 1, dt = 2 /' // nl // &
            '&rod n_elements = 2, lenght = 1, ' // direct // ' /' // nl
        call parse(text, scene, errors, 2, file='y.nml')
        CHECK_CONTAINS(errors%joined(), 'y.nml:2: &rod: unknown variable "lenght"', 'misspelling')
        CHECK_CONTAINS(errors%joined(), 'did you mean "length"?', 'suggestion')
        CHECK_CONTAINS(errors%joined(), 'y.nml:2: &rod length: required but not given', 'required')
        CHECK_EQUAL(index(errors%joined(), 'larger than t_end'), 0, 'no cross-check')
        text = '&time t_end = 1, dt = 2 /' // nl // &
            '&rod n_elements = 2, length = 1, ' // direct // ' /' // nl
        call parse(text, scene, errors, 1, file='y.nml')
        CHECK_CONTAINS(errors%joined(), 'y.nml: &time dt: 2.0 is larger than t_end = 1.0', 'dt')
    end subroutine test_read_errors_skip_cross_checks

    subroutine test_section_errors()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text, joined, fragment
        text = '&time t_end = 1, dt = 0.5 /' // nl // &
            "&rod n_elements = 2, length = 1, section = 'tube', radius = 0.05," // &
            ' inner_radius = 0.05, E = 1e9, nu = 0.3, density = 1000 /' // nl // &
            "&rod n_elements = 2, length = 1, section = 'circle', radius = 0.05," // &
            ' E = 1e9, density = 1000 /' // nl // &
            "&rod n_elements = 2, length = 1, section = 'rectangle', width = 0.1," // &
            " torsion_constant = 'polar', E = 1e9, nu = 0.3, density = 1000 /" // nl
        call parse(text, scene, errors, 3, file='z.nml')
        joined = errors%joined()
        CHECK_CONTAINS(joined, "z.nml:2: &rod 'rod1' inner_radius: 0.05 must be smaller", 'tube')
        CHECK_CONTAINS(joined, 'than radius = 0.05', 'tube radius')
        CHECK_CONTAINS(joined, "z.nml:3: &rod 'rod2' G: give G or nu with a section", 'G')
        fragment = "z.nml:4: &rod 'rod3' height: required with section = 'rectangle'"
        CHECK_CONTAINS(joined, fragment, 'height')
    end subroutine test_section_errors


    ! Every variable of every implemented group has an example, which the reader accepts (with
    ! the condition of an only_if variable given too); descriptions fit their field.
    subroutine test_every_example_reads()
        type(group_spec_t), allocatable :: groups(:)
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text, condition, variable, value, where
        integer :: g, v
        logical :: fits
        groups = input_groups()
        do g = 1, size(groups)
            if (.not. groups(g)%implemented) cycle
            do v = 1, size(groups(g)%variables)
                associate (spec => groups(g)%variables(v))
                    CHECK_TRUE(len_trim(spec%example) > 0, 'example of ' // trim(spec%name))
                    fits = len_trim(spec%description) < len(spec%description)
                    CHECK_TRUE(fits, 'description fits: ' // trim(spec%name))
                    condition = ''
                    if (len_trim(spec%only_if) > 0) then
                        call split_condition(spec%only_if, variable, value)
                        condition = variable // " = '" // value // "', "
                    end if
                    text = '&' // trim(groups(g)%name) // ' ' // condition // trim(spec%name) // ' = ' // &
                        trim(spec%example) // ' /' // nl
                    errors = error_list_t()
                    call read_scene_text(text, 'example.nml', scene, errors)
                    where = '&' // trim(groups(g)%name) // ' ' // trim(spec%name) // ':'
                    if (errors%count > 0) then
                        CHECK_TRUE(index(errors%joined(), where) == 0, 'example reads: ' // errors%joined())
                    end if
                end associate
            end do
        end do
    end subroutine test_every_example_reads

    ! A string array (&plate rods): quoted names separated by commas or blanks, a subscripted
    ! entry, a doubled quote inside a name; unquoted entries, text after a quoted one and repeat
    ! counts are refused; &contact is marked given at its line, and absent it stays off.
    subroutine test_string_arrays()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: text, joined
        text = '&plate name = ''p'', end = ''end'', rods = ''a'', "b" ''c''   ''it''''s'' /' // nl // &
            '&contact stiffness = 1 /' // nl // &
            '&plate name = ''q'', end = ''end'', rods(6) = ''f'' /' // nl
        call read_scene_text(text, 'arrays.nml', scene, errors)
        CHECK_EQUAL(errors%count, 0, 'read: ' // errors%joined())
        if (size(scene%plates) /= 2) return
        CHECK_EQUAL(trim(scene%plates(1)%rods(1)), 'a', 'first')
        CHECK_EQUAL(trim(scene%plates(1)%rods(2)), 'b', 'double quotes')
        CHECK_EQUAL(trim(scene%plates(1)%rods(3)), 'c', 'blank separator')
        CHECK_EQUAL(trim(scene%plates(1)%rods(4)), "it's", 'doubled quote')
        CHECK_EQUAL(len_trim(scene%plates(1)%rods(5)), 0, 'four rods')
        CHECK_EQUAL(trim(scene%plates(2)%rods(6)), 'f', 'subscripted entry')
        CHECK_EQUAL(len_trim(scene%plates(2)%rods(1)), 0, 'before it blank (resolve refuses the gap)')
        CHECK_TRUE(scene%contact%given, '&contact given')
        CHECK_EQUAL(scene%contact%input_line, 2, '&contact line')
        errors = error_list_t()
        text = "&plate rods = 'a', b /" // nl // "&plate rods = 'a'x /" // nl // &
            "&plate rods = 2*'a' /" // nl
        call read_scene_text(text, 'arrays.nml', scene, errors)
        joined = errors%joined()
        CHECK_CONTAINS(joined, "arrays.nml:1: &plate rods: expects quoted strings separated by commas", 'b')
        CHECK_CONTAINS(joined, "arrays.nml:2: &plate rods: expects quoted strings", 'a''x')
        CHECK_CONTAINS(joined, "arrays.nml:3: &plate rods: expects quoted strings", 'repeat')
        CHECK_TRUE(.not. scene%contact%given, 'no &contact: contact off')
        errors = error_list_t()
        call read_scene_text('&time t_end = 1 /' // nl, 'none.nml', scene, errors)
        CHECK_TRUE(.not. scene%contact%given, 'contact off by default')
        CHECK_EQUAL(size(scene%plates), 0, 'no plates')
    end subroutine test_string_arrays

    ! required_if and only_if: a helix needs its three variables, a straight rod its length, and
    ! helix or polyline variables are refused with another geometry; each names the condition.
    subroutine test_conditional_variables()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        character(len=:), allocatable :: joined
        call parse("&time t_end = 1, dt = 0.5 /" // nl // "&rod n_elements = 2, geometry = 'helix', " // &
            direct // ' /' // nl // "&rod n_elements = 2, points = 0, 0, 0, 1, 0, 0, " // direct // &
            ' /' // nl, scene, errors, 5, 'cond.nml')
        joined = errors%joined()
        CHECK_CONTAINS(joined, "cond.nml:2: &rod helix_radius: required but not given (geometry = 'helix')", 'r')
        CHECK_CONTAINS(joined, "cond.nml:2: &rod helix_pitch: required but not given (geometry = 'helix')", 'p')
        CHECK_CONTAINS(joined, "cond.nml:2: &rod helix_turns: required but not given (geometry = 'helix')", 't')
        CHECK_CONTAINS(joined, "cond.nml:3: &rod length: required but not given (geometry = 'straight')", 'L')
        CHECK_CONTAINS(joined, "cond.nml:3: &rod points: only used with geometry = 'polyline' (here geometry = 'straight')", 'pts')
    end subroutine test_conditional_variables
end module rs_test_io_input_reader

!> Test program: runs the tests of rs_test_io_input_reader; exits non-zero if any failed.
program test_input_reader
    use rs_test_io_input_reader, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_input_reader
