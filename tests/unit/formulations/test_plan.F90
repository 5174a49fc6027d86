#include "rs_assert.h"
!> Unit tests of rs_formulations_plan and rs_ph_director_plan (the plan of --check-input,
!> DESIGN.md §4) on parsed scenes: the counts of nodes, Newton unknowns, stresses and
!> multipliers against hand counts, what is skipped (Maxwell variables without branches,
!> constraint multipliers without a constraint, mass terms in a quasistatic run, actuators) and
!> why condensation is ignored, the formulation's origin, steps and records, the round-robin
!> ranks, the units; and that the plan is comments only: the resolved scene followed by its
!> plan reads back to the same scene. For the planar formulations (rs_ph_planar_plan): what
!> 'auto' chose and why, the plane and planar coordinates, the unknowns (3 per node + 3 per
!> element, 3 per node when condensed or for cl_em_planar), supports and joints. For a
!> ph_director bundle (issue 10): its joints by kind, plates, supports and contact settings.
module rs_test_formulations_plan
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_list_t
    use rs_test_assert, only: run_test, assert_true, assert_equal, assert_contains
    use rs_model_scene, only: scene_t
    use rs_model_damping, only: damping_plan_text
    use rs_io_input_file, only: parse_scene
    use rs_io_scene_writer, only: resolved_scene_text
    use rs_formulations_plan, only: scene_plan_text, plan_header
    use rs_formulations_formulation, only: rod_formulation_t
    use rs_formulations_factory, only: create_formulation
    use rs_formulations_rod_sizes, only: rod_sizes_t, rod_sizes_of
    use rs_core_error, only: error_t
    implicit none
    private

    public :: run_all_tests

    character(len=*), parameter :: nl = new_line('a')

contains

    subroutine run_all_tests()
        call run_test('cantilever_counts', test_cantilever_counts)
        call run_test('condensed_counts', test_condensed_counts)
        call run_test('extensions_and_skips', test_extensions_and_skips)
        call run_test('ph_director_damping', test_ph_director_damping)
        call run_test('ranks_and_origins', test_ranks_and_origins)
        call run_test('helix_and_units', test_helix_and_units)
        call run_test('plan_is_comments', test_plan_is_comments)
        call run_test('planar_plan', test_planar_plan)
        call run_test('auto_3d_reason', test_auto_3d_reason)
        call run_test('bundle_plan', test_bundle_plan)
        call run_test('strand_step', test_strand_step)
        call run_test('se3_pg_damping', test_se3_pg_damping)
        call run_test('continuation_plan', test_continuation_plan)
        call run_test('long_rod_counts', test_long_rod_counts)
        call run_test('sizes_extend_exactly', test_sizes_extend_exactly)
    end subroutine run_all_tests

    !> A clamped-free rod of 4 quadratic elements (9 nodes, 8 free) with an end load.
    function cantilever(extra_rod, extra_groups) result(text)
        character(len=*), intent(in) :: extra_rod, extra_groups
        character(len=:), allocatable :: text
        text = '&time t_end = 1, dt = 0.3 /' // nl // &
            '&output stride = 3 /' // nl // &
            "&rod name = 'beam', n_elements = 4, length = 2, EA = 1e4, GA1 = 1e4, GA2 = 1e4," // nl // &
            '     EI1 = 10, EI2 = 10, GJ = 10, rhoA = 1, rhoI1 = 0.1, rhoI2 = 0.1' // extra_rod // ' /' // nl // &
            "&bc rod = 'beam', end = 'start', kind = 'clamped' /" // nl // &
            "&load rod = 'beam', where = 'end', force = 0, 0, -1 /" // nl // extra_groups
    end function cantilever

    function plan_of(text, n_ranks) result(plan)
        character(len=*), intent(in) :: text
        integer, intent(in) :: n_ranks
        character(len=:), allocatable :: plan
        type(scene_t) :: scene
        type(error_list_t) :: errors
        call parse_scene(text, 'plan.nml', scene, errors)
        CHECK_EQUAL(errors%count, 0, 'scene valid: ' // errors%joined())
        plan = ''
        if (errors%count > 0) return
        plan = scene_plan_text(scene, n_ranks)
    end function plan_of

    ! 8 free nodes x 30 + 4 elements x 12 stresses (6 components x 2 coefficients) = 288.
    subroutine test_cantilever_counts()
        character(len=:), allocatable :: plan
        plan = plan_of(cantilever('', ''), 1)
        CHECK_CONTAINS(plan, plan_header // nl, 'header')
        CHECK_CONTAINS(plan, 'unknowns: 288 Newton unknowns = 8 free nodes x 30', 'unknowns')
        CHECK_CONTAINS(plan, '+ 4 elements x 12 stresses', 'stresses')
        CHECK_CONTAINS(plan, '4 elements of degree 2, 9 nodes', 'mesh')
        CHECK_CONTAINS(plan, 'orthonormality multipliers: 6 per node whose rotation is free (48)', 'multipliers')
        CHECK_CONTAINS(plan, 'constraint multipliers: none', 'no constraint')
        CHECK_CONTAINS(plan, 'Maxwell internal variables: none', 'no branches')
        CHECK_CONTAINS(plan, 'mass terms: consistent mass', 'dynamics has mass')
        CHECK_CONTAINS(plan, 'actuators: none', 'no actuators')
        CHECK_CONTAINS(plan, 'loads: 1 end load(s), 0 distributed, 0 gravity', 'loads')
        CHECK_CONTAINS(plan, 'supports: start clamped', 'clamped start')
        CHECK_CONTAINS(plan, 'initial velocity: at rest', 'at rest')
        CHECK_CONTAINS(plan, 'stress condensation: off', 'condensation off')
        ! t_end = 1, dt = 0.3: 4 steps (the last 0.1); stride 3: records at 0, step 3, step 4.
        CHECK_CONTAINS(plan, 'time: 4 midpoint step(s) of dt = 0.3 s', 'steps')
        CHECK_CONTAINS(plan, '3 record(s)', 'records')
        CHECK_CONTAINS(plan, 'stress-free initial geometry', 'stress-free reference')
    end subroutine test_cantilever_counts

    ! se3_strand's step: semi-implicit, one linear solve, no Newton (issue 21 item 15); the
    ! scene-level lines say so instead of 'midpoint' and the Newton tolerance.
    subroutine test_strand_step()
        character(len=:), allocatable :: plan
        plan = plan_of("&time t_end = 1, dt = 0.25 /" // nl // &
            "&rod formulation = 'se3_strand', n_elements = 4, length = 1, section = 'circle', " // &
            "radius = 0.01, E = 2e11, nu = 0.3, density = 7800 /" // nl // &
            "&bc rod = 'rod1', end = 'start', kind = 'clamped' /" // nl, 1)
        CHECK_CONTAINS(plan, 'time: 4 semi-implicit step(s) of dt = 0.25', 'semi-implicit steps')
        CHECK_CONTAINS(plan, 'Newton: none, one linear solve per step', 'no Newton')
        CHECK_TRUE(index(plan, 'midpoint step') == 0, 'no midpoint steps')
    end subroutine test_strand_step

    ! A damped se3_pg rod's plan shows its damping in damping_plan_text's words (issue 26 item 1).
    subroutine test_se3_pg_damping()
        character(len=*), parameter :: expected = 'damping: Kelvin-Voigt 1.000E-03 s ' // &
            '(every component); drag 5.000E-01 N s/m^2'
        character(len=:), allocatable :: plan
        plan = plan_of(cantilever(", formulation = 'se3_pg', kelvin_voigt_time = 1e-3, " // &
            'drag = 0.5', ''), 1)
        CHECK_CONTAINS(plan, expected, 'damping line')
        plan = plan_of(cantilever(", formulation = 'se3_pg'", ''), 1)
        CHECK_TRUE(index(plan, 'damping:') == 0, 'no damping line for an undamped rod')
    end subroutine test_se3_pg_damping

    ! An arc-length continuation (issue 27 item 3, &time continuation): its path steps replace
    ! the load steps and the endpoint solve (the time line says how many, the smallest step
    ! arc_length / 4^max_cutbacks and where the path ends), the bordered solves and the records'
    ! load times are named, se3_pg's statics follow the path, and modes after it say about which
    ! point and with the loads of which time they are; a load-stepped run keeps its lines.
    subroutine test_continuation_plan()
        character(len=*), parameter :: path = "&time t_end = 1, dt = 1, quasistatic = .true., " // &
            "continuation = 'arc_length', arc_length = 0.02, arc_length_max = 0.1, " // &
            "path_steps = 50 /" // nl // "&solver max_cutbacks = 3 /" // nl // &
            "&modes about = 'equilibrium', n_modes = 2 /" // nl
        character(len=*), parameter :: bounds = 'between 3.125e-04 (arc_length / ' // &
            '4^max_cutbacks) and arc_length_max = 0.1'
        character(len=:), allocatable :: plan
        plan = plan_of(path // "&output stride = 1 /" // nl // &
            "&rod formulation = 'se3_pg', n_elements = 4, length = 1, section = 'circle', " // &
            "radius = 0.01, E = 2e11, nu = 0.3, density = 7800 /" // nl // &
            "&bc rod = 'rod1', end = 'start', kind = 'clamped' /" // nl // &
            "&load rod = 'rod1', where = 'end', force = -1, 0, 0 /" // nl, 1)
        CHECK_CONTAINS(plan, 'time: quasistatic by arc-length continuation', 'continuation')
        CHECK_CONTAINS(plan, 'at most 50 path step(s), the first of arc length 0.02', 'path steps')
        CHECK_CONTAINS(plan, bounds, 'step bounds')
        CHECK_CONTAINS(plan, 'passes t_end = 1.0; dt is not used', 'end of the path')
        CHECK_CONTAINS(plan, 'bordered solves: ', 'bordered solves')
        CHECK_CONTAINS(plan, 'no endpoint solve', 'no endpoint solve')
        CHECK_CONTAINS(plan, 'at most 51 record(s)', 'records')
        CHECK_CONTAINS(plan, '/rods/NAME/series/load_time', 'load times')
        CHECK_CONTAINS(plan, 'statics: Newton at the points of the arc-length path', 'se3_pg')
        CHECK_CONTAINS(plan, 'after the continuation: about the path''s last point', 'modes')
        ! Its loads are those of its own load time, not t_end's (rs_app_run_modes).
        CHECK_CONTAINS(plan, 'last point, with the loads of its load time', 'modes'' loads')
        CHECK_TRUE(index(plan, 'loads of t_end') == 0, 'not the loads of t_end')
        CHECK_TRUE(index(plan, 'load step(s)') == 0, 'no load steps')
        CHECK_TRUE(index(plan, 'statics: Newton at each load factor') == 0, 'no load factors')
        plan = plan_of(cantilever(", formulation = 'se3_pg'", ''), 1)
        CHECK_TRUE(index(plan, 'continuation') == 0, 'no continuation without it')
    end subroutine test_continuation_plan

    ! A rod longer than the plan's small builds (issue 21 item 17: the plan builds at most 3
    ! elements and extends the sizes): 40 quadratic elements clamped at both ends, 81 nodes, 79
    ! free: 79 x 30 + 40 x 12 = 2850 unknowns; condensed 79 x 18 = 1422.
    subroutine test_long_rod_counts()
        character(len=:), allocatable :: plan, scene, expected
        scene = replace(cantilever('', "&bc rod = 'beam', end = 'end', kind = 'clamped' /" // nl), &
            'n_elements = 4', 'n_elements = 40')
        plan = plan_of(scene, 1)
        CHECK_CONTAINS(plan, '40 elements of degree 2, 81 nodes', 'mesh')
        CHECK_CONTAINS(plan, 'unknowns: 2850 Newton unknowns = 79 free nodes x 30', 'unknowns')
        CHECK_CONTAINS(plan, 'orthonormality multipliers: 6 per node whose rotation is free (474)', 'multipliers')
        expected = 'supports: start clamped (no unknowns at its node), end clamped'
        CHECK_CONTAINS(plan, expected, 'supports')
        plan = plan_of(scene // '&solver condense_stresses = .true. /' // nl, 1)
        CHECK_CONTAINS(plan, 'unknowns: 1422 Newton unknowns = 79 free nodes x 18', 'condensed')
        CHECK_CONTAINS(plan, '!   memory: estimated peak ', 'memory line')
        CHECK_CONTAINS(plan, 'unknowns, state ', 'rod memory line')
    end subroutine test_long_rod_counts

    ! The sizes the plan and the memory estimate extend from builds of 3 and 4 elements equal
    ! those of the rod built at its full size, for every formulation and for supports, loads,
    ! constraints, branches, degrees and condensation that change the ends or the elements.
    subroutine test_sizes_extend_exactly()
        character(len=*), parameter :: material = ', length = 2, EA = 1e4, GA1 = 1e4, ' // &
            'GA2 = 1e4, EI1 = 10, EI2 = 10, GJ = 10, rhoA = 1, rhoI1 = 0.1, rhoI2 = 0.1'
        character(len=*), parameter :: clamp = "&bc rod = 'r', end = 'start', kind = 'clamped' /"
        call check("&rod name = 'r', n_elements = 37" // material // ' /' // nl // clamp, &
            'ph_director clamped-free')
        call check("&rod name = 'r', n_elements = 23, degree = 1" // material // &
            ", constraint = 'kirchhoff', maxwell_fraction = 0.2, maxwell_tau_E = 0.1 /" // nl // &
            clamp // nl // "&bc rod = 'r', end = 'end', kind = 'clamped' /", &
            'ph_director degree 1, kirchhoff, a branch, clamped-clamped')
        call check("&solver condense_stresses = .true. /" // nl // "&rod name = 'r', " // &
            "n_elements = 31" // material // ' /' // nl // clamp // nl // &
            "&load rod = 'r', where = 'end', force = 0, 0, 1 /", 'ph_director condensed')
        call check("&rod name = 'r', formulation = 'ph_planar', n_elements = 29" // material // &
            ' /' // nl // clamp, 'ph_planar')
        call check("&rod name = 'r', formulation = 'cl_em_planar', n_elements = 29" // &
            material // ' /' // nl // clamp, 'cl_em_planar')
        call check("&rod name = 'r', formulation = 'se3_pg', n_elements = 19" // material // &
            ' /' // nl // clamp, 'se3_pg')
        call check("&rod name = 'r', formulation = 'se3_strand', n_elements = 19" // &
            material // ' /' // nl // clamp, 'se3_strand')
    contains
        subroutine check(groups, what)
            character(len=*), intent(in) :: groups, what
            type(scene_t) :: scene
            type(error_list_t) :: errors
            type(rod_sizes_t) :: sizes
            type(error_t), allocatable :: err
            class(rod_formulation_t), allocatable :: rod
            integer, allocatable :: row_ptr(:), cols(:)
            call parse_scene('&time t_end = 1, dt = 0.5 /' // nl // groups // nl, 'sizes.nml', &
                scene, errors)
            CHECK_EQUAL(errors%count, 0, what // ': scene valid: ' // errors%joined())
            if (errors%count > 0) return
            call create_formulation(trim(scene%rods(1)%formulation), rod, err)
            if (.not. allocated(err)) call rod_sizes_of(scene, 1, sizes, err, rod)
            CHECK_TRUE(.not. allocated(err), what // ': sized')
            if (.not. allocated(err)) call rod%init(scene, [1], err)
            CHECK_TRUE(.not. allocated(err), what // ': built')
            if (allocated(err)) return
            call rod%jacobian_pattern(row_ptr, cols)
            CHECK_EQUAL(int(sizes%n_elements), scene%rods(1)%n_elements, what // ': elements')
            CHECK_EQUAL(int(sizes%n_unknown), rod%n_unknown(), what // ': unknowns')
            CHECK_EQUAL(int(sizes%n_state), rod%n_state(), what // ': state')
            CHECK_EQUAL(int(sizes%n_nonzeros), size(cols), what // ': Jacobian non-zeros')
        end subroutine check
    end subroutine test_sizes_extend_exactly

    ! Condensed: 18 unknowns per free node.
    subroutine test_condensed_counts()
        character(len=:), allocatable :: plan
        plan = plan_of(cantilever('', '&solver condense_stresses = .true. /' // nl), 1)
        CHECK_CONTAINS(plan, 'unknowns: 144 Newton unknowns = 8 free nodes x 18', 'condensed unknowns')
        CHECK_CONTAINS(plan, 'stress condensation: on', 'condensation on')
    end subroutine test_condensed_counts

    ! Kirchhoff, two Maxwell branches, a tendon, quasistatic, condensation asked for:
    ! 8 x 30 + 4 x (6 x 2 x 3) = 384 unknowns; 2 x 2 x 4 = 16 shear multipliers.
    subroutine test_extensions_and_skips()
        character(len=:), allocatable :: plan, expected
        plan = plan_of(replace(cantilever(", constraint = 'kirchhoff', maxwell_fraction = 0.2, 0.1," // &
            nl // '     maxwell_tau_E = 0.1, 1.0', &
            '&solver condense_stresses = .true. /' // nl // &
            "&actuator rod = 'beam', kind = 'tendon', offset = 0, 0.01, tension = 1 /" // nl), &
            '&time t_end = 1, dt = 0.3 /', '&time t_end = 1, dt = 0.3, quasistatic = .true. /'), 1)
        CHECK_CONTAINS(plan, 'unknowns: 384 Newton unknowns', 'unknowns with branches')
        CHECK_CONTAINS(plan, "constraint = 'kirchhoff': N1, N2 (16 coefficients) are multipliers", 'shear multipliers')
        CHECK_CONTAINS(plan, 'Maxwell internal variables: 2 branch(es), 24 branch stresses', 'branches')
        CHECK_CONTAINS(plan, 'mass terms: skipped (quasistatic', 'no mass')
        CHECK_CONTAINS(plan, 'actuators: 0 pneumatic chamber(s), 1 tendon(s)', 'tendon')
        expected = 'requested but ignored: constrained components, Maxwell branches, a quasistatic run'
        CHECK_CONTAINS(plan, expected, 'why condensation is ignored')
        CHECK_CONTAINS(plan, 'time: quasistatic, 4 midpoint load step(s)', 'load steps')
    end subroutine test_extensions_and_skips

    ! A ph_director rod's damping (issue 26 item 1): the plan shows damping_plan_text of the
    ! resolved rod and how it is built (Kelvin-Voigt condensed, so the unknowns are those of
    ! the undamped cantilever; none on constrained components); an undamped rod skips it.
    subroutine test_ph_director_damping()
        character(len=:), allocatable :: plan, text
        type(scene_t) :: scene
        type(error_list_t) :: errors
        plan = plan_of(cantilever('', ''), 1)
        CHECK_CONTAINS(plan, 'damping: none (no kelvin_voigt_time, drag, angular_drag: skipped)', 'none')
        text = cantilever(", kelvin_voigt_time = 1e-3, drag = 0.5, constraint = 'kirchhoff'", '')
        call parse_scene(text, 'plan.nml', scene, errors)
        CHECK_EQUAL(errors%count, 0, 'damped scene valid: ' // errors%joined())
        plan = plan_of(text, 1)
        CHECK_CONTAINS(plan, 'damping: ' // damping_plan_text(scene%rods(1)), 'damping_plan_text')
        CHECK_CONTAINS(plan, 'its midpoint stress condensed per element (no unknowns)', 'condensed')
        CHECK_CONTAINS(plan, 'none on the constrained components', 'constrained')
        CHECK_CONTAINS(plan, 'unknowns: 288 Newton unknowns', 'no unknowns added')
        plan = plan_of(cantilever(', angular_drag = 2e-3', ''), 1)
        CHECK_CONTAINS(plan, 'damping: angular drag ', 'angular drag alone')
    end subroutine test_ph_director_damping

    ! Four rods on 3 ranks: rods 1 and 4 on rank 0; the origin of each formulation.
    subroutine test_ranks_and_origins()
        character(len=:), allocatable :: plan, rod
        rod = ', n_elements = 2, length = 1, EA = 1, GA1 = 1, GA2 = 1, EI1 = 1, EI2 = 1, GJ = 1,' // &
            ' rhoA = 1, rhoI1 = 1, rhoI2 = 1 /' // nl
        plan = plan_of('&run formulation_default = ''auto'' /' // nl // '&time t_end = 1, dt = 0.5 /' // &
            nl // "&rod name = 'a'" // rod // "&rod name = 'b', formulation = 'ph_director'" // rod // &
            "&rod name = 'c'" // rod // "&rod name = 'd'" // rod, 3)
        CHECK_CONTAINS(plan, 'ranks: 4 rod(s) in 4 system(s)', 'ranks')
        CHECK_CONTAINS(plan, "rod 'a' on rank 0: ph_planar (auto: the rods, loads and velocities", 'auto')
        CHECK_CONTAINS(plan, "rod 'b' on rank 1: ph_director (given in &rod)", 'given')
        CHECK_CONTAINS(plan, "rod 'c' on rank 2:", 'third rank')
        CHECK_CONTAINS(plan, "rod 'd' on rank 0:", 'round robin')
        plan = plan_of('&time t_end = 1, dt = 0.5 /' // nl // "&rod name = 'a'" // rod, 1)
        CHECK_CONTAINS(plan, "rod 'a' on rank 0: ph_director (from &run formulation_default)", 'default')
        CHECK_CONTAINS(plan, 'supports: start free', 'free ends')
    end subroutine test_ranks_and_origins

    ! Two rods in the plane z = 1 joined by a revolute joint, the first pinned, under gravity
    ! along -e_y, chosen by 'auto': ph_planar, its plane and coordinates; 5 + 3 nodes and 4 + 2
    ! elements: 15 + 12 = 27 and 9 + 6 = 15 unknowns, 2 fixed by the pin; condensed 15 and 9;
    ! as cl_em_planar 15 and 9 with no element unknowns.
    subroutine test_planar_plan()
        character(len=:), allocatable :: plan, text, rod, expected
        rod = ' EA = 1, GA1 = 1, GA2 = 1, EI1 = 1, EI2 = 1, GJ = 1, rhoA = 1, rhoI1 = 1, rhoI2 = 1 /' // nl
        text = "&run formulation_default = 'auto' /" // nl // '&time t_end = 1, dt = 0.5 /' // nl // &
            "&rod name = 'a', n_elements = 4, length = 2, start = 0, 0, 1, direction = 0, -1, 0," // rod // &
            "&rod name = 'b', n_elements = 2, length = 1, start = 0, -2, 1," // rod // &
            "&bc rod = 'a', end = 'start', kind = 'pinned' /" // nl // &
            "&joint rod_a = 'a', end_a = 'end', rod_b = 'b', end_b = 'start', kind = 'revolute' /" // nl // &
            "&load where = 'gravity', acceleration = 0, -9.81, 0 /" // nl
        plan = plan_of(text, 1)
        expected = "rod 'a' on rank 0: ph_planar (auto: the rods, loads and velocities lie in the " // &
            'plane through (0.0, 0.0, 1.0) with normal (0.0, 0.0, 1.0))'
        CHECK_CONTAINS(plan, expected, 'auto chose ph_planar')
        CHECK_CONTAINS(plan, "rod 'b' on rank 0: ph_planar (auto:", 'the joined rod too')
        CHECK_CONTAINS(plan, "shared with the joined rod(s) 'b'", 'one plane for the system')
        ! The joined rods are one system: on two ranks both run on rank 0.
        CHECK_CONTAINS(plan_of(text, 2), "rod 'b' on rank 0:", 'a joined rod runs with its system')
        CHECK_CONTAINS(plan_of(text, 2), 'ranks: 2 rod(s) in 1 system(s)', 'one system')
        expected = 'geometry: straight from (x, y) = (0.0, -2.0) m at theta_0 = 0.0 rad, length 1.0 m'
        CHECK_CONTAINS(plan, expected, 'planar coordinates of rod b')
        CHECK_CONTAINS(plan, 'theta_0 = -1.5707963267948966 rad', 'angle of rod a')
        expected = 'unknowns: 3 x 5 nodes (x, y, theta) + 3 x 4 elements (Gamma1, Gamma2, kappa) = 27, less 2'
        CHECK_CONTAINS(plan, expected, 'uncondensed unknowns of rod a')
        CHECK_CONTAINS(plan, 'supports: start pinned (x, y fixed, theta free), end free', 'pin')
        expected = "joints: 'start' end revolute with the 'end' end of rod 'a' (shared nodal x, y, own theta"
        CHECK_CONTAINS(plan, expected, 'joint of rod b')
        CHECK_CONTAINS(plan, 'gravity g = (0.0, -9.81) m/s^2 in the plane', 'gravity in planar coordinates')
        plan = plan_of(text // '&solver condense_stresses = .true. /' // nl, 1)
        expected = 'unknowns: 3 x 3 nodes (x, y, theta) = 9, less 0 fixed by supports; the 3 x 2 element ' // &
            'strains are condensed'
        CHECK_CONTAINS(plan, expected, 'condensed unknowns of rod b')
        plan = plan_of(replace(text, "&run formulation_default = 'auto' /", &
            "&run formulation_default = 'cl_em_planar' /"), 1)
        CHECK_CONTAINS(plan, "rod 'a' on rank 0: cl_em_planar (from &run formulation_default)", 'cl_em')
        expected = 'unknowns: 3 x 5 nodes (x, y, theta) = 15, less 2 fixed by supports; no element unknowns'
        CHECK_CONTAINS(plan, expected, 'cl_em unknowns')
        CHECK_CONTAINS(plan, 'axial and shear terms at 1 Gauss point (reduced, free of shear locking)', 'quadrature: reduced by default')
    end subroutine test_planar_plan

    ! 'auto' on a rod pushed out of its plane: ph_director, and the reason names the load.
    subroutine test_auto_3d_reason()
        character(len=:), allocatable :: plan, expected
        plan = plan_of("&run formulation_default = 'auto' /" // nl // cantilever('', &
            "&load rod = 'beam', where = 'distributed', force = 0, 1, 0 /" // nl), 1)
        expected = "rod 'beam' on rank 0: ph_director (auto: 3D because load 2 (line 8): force (0.0, " // &
            '1.0, 0.0) has a component along the plane normal (0.0, 1.0, 0.0)'
        CHECK_CONTAINS(plan, expected, '3D reason')
        CHECK_CONTAINS(plan, 'unknowns: 288 Newton unknowns', 'ph_director plan follows')
    end subroutine test_auto_3d_reason

    ! A spinning helix in mm, tonne, s: geometry, initial rigid motion and unit names.
    subroutine test_helix_and_units()
        character(len=:), allocatable :: plan, expected
        plan = plan_of("&run units = 'mm_tonne_s' /" // nl // '&time t_end = 1, dt = 0.5 /' // nl // &
            "&rod name = 'spring', n_elements = 6, geometry = 'helix', helix_radius = 10," // nl // &
            '     helix_pitch = 4, helix_turns = 2, direction = 0, 0, 1, angular_velocity = 0, 0, 3,' // nl // &
            '     EA = 1, GA1 = 1, GA2 = 1, EI1 = 1, EI2 = 1, GJ = 1, rhoA = 1, rhoI1 = 1, rhoI2 = 1 /' // nl, 1)
        expected = 'geometry: helix of radius 10.0 mm, pitch 4.0 mm, 2.0 turns, axis through ' // &
            '(-10.0, 0.0, 0.0) along (0.0, 0.0, 1.0)'
        CHECK_CONTAINS(plan, expected, 'helix')
        expected = 'initial velocity: rigid motion v = (0.0, 0.0, 0.0) mm/s + (0.0, 0.0, 3.0) ' // &
            'rad/s x (phi - (0.0, 0.0, 0.0))'
        CHECK_CONTAINS(plan, expected, 'spin')
        expected = "units: 'mm_tonne_s' (length mm, mass tonne, time s, force N, stress MPa)"
        CHECK_CONTAINS(plan, expected, 'units')
        CHECK_CONTAINS(plan, 'rhoI = 1.0, 1.0 tonne mm', 'inertia unit')
    end subroutine test_helix_and_units

    ! The plan is comments: every line starts with '!', and the resolved text followed by the
    ! plan parses to a scene whose resolved text is the same.
    subroutine test_plan_is_comments()
        type(scene_t) :: scene, again
        type(error_list_t) :: errors
        character(len=:), allocatable :: plan, text
        integer :: start, eol
        call parse_scene(cantilever('', ''), 'plan.nml', scene, errors)
        CHECK_EQUAL(errors%count, 0, 'valid')
        plan = scene_plan_text(scene, 2)
        start = 1
        do while (start <= len(plan))
            eol = index(plan(start:), nl)
            CHECK_EQUAL(plan(start:start), '!', 'comment line: ' // plan(start:start + eol - 2))
            start = start + eol
        end do
        text = resolved_scene_text(scene)
        call parse_scene(text // plan, 'plan.nml', again, errors)
        CHECK_EQUAL(errors%count, 0, 'resolved text with the plan parses: ' // errors%joined())
        CHECK_TRUE(resolved_scene_text(again) == text, 'the plan does not change the scene')
    end subroutine test_plan_is_comments

    ! A bundle (issue 10): each ph_director rod's plan names its joints by kind with the other
    ! end, the plates it is tied to (with their rods and drive), the supports held by them, and
    ! the contact settings (derived margin and skip); a scene without them says 'none'.
    subroutine test_bundle_plan()
        character(len=:), allocatable :: plan, expected, rods
        rods = "&rod name = 'a', n_elements = 4, length = 1, section = 'circle', radius = 0.01," // nl // &
            '     E = 1e9, nu = 0.3, density = 1000 /' // nl // &
            "&rod name = 'b', n_elements = 4, length = 1, start = 1, 0, 0, direction = 0, 1, 0," // nl // &
            "     section = 'circle', radius = 0.01, contact_radius = 0.025, E = 1e9, nu = 0.3," // nl // &
            '     density = 1000 /' // nl
        plan = plan_of('&time t_end = 1, dt = 0.5 /' // nl // rods // &
            "&joint rod_a = 'a', end_a = 'end', rod_b = 'b', end_b = 'start', kind = 'revolute'," // nl // &
            '       axis = 0, 0, 1 /' // nl // &
            "&plate name = 'foot', rods = 'a', end = 'start' /" // nl // &
            "&plate name = 'hand', rods = 'b', end = 'end', rotation = 0, 0.5, 0," // nl // &
            "       time_function = 'ramp', t_off = 1 /" // nl // &
            '&contact stiffness = 1e9, self_contact = .false. /' // nl, 1)
        expected = "joints: 1 (0 rigid, 0 spherical, 1 revolute), constraints with multipliers on " // &
            "the end nodes: 'end' end revolute with the 'start' end of rod 'b' (position tied, " // &
            'relative rotation about (0.0, 0.0, 1.0) only; &joint at line 7)'
        CHECK_CONTAINS(plan, expected, 'joints of a')
        expected = "supports: start tied to &plate 'foot' (multipliers), end jointed (multipliers)"
        CHECK_CONTAINS(plan, expected, 'supports of a')
        expected = "end plates: 'foot' at the 'start' end of 'a', fixed (6 constraint rows per " // &
            'tied end; &plate at line 9)'
        CHECK_CONTAINS(plan, expected, 'fixed plate')
        expected = "end plates: 'hand' at the 'end' end of 'b', driven: displacement f(t) (0.0, " // &
            "0.0, 0.0) m and rotation f(t) (0.0, 0.5, 0.0) rad about (1.0, 1.0, 0.0), f = 'ramp'"
        CHECK_CONTAINS(plan, expected, 'driven plate about the mean of its ends')
        expected = "contact: stiffness 1.0e+09 N/m^3, contact radius 0.01 m, margin 0.025 m, " // &
            "skip 2 element(s) along a rod, points per element: derived, self contact off, " // &
            "frictionless; candidate pairs " // &
            'from a cell grid rebuilt every step'
        CHECK_CONTAINS(plan, expected, 'contact of a: derived margin and skip')
        CHECK_CONTAINS(plan, 'contact radius 0.025 m', 'contact radius of b')
        CHECK_CONTAINS(plan, 'note: the contact radius is 2.5 times the section radius 0.01 m', 'note')
        CHECK_CONTAINS(plan, 'ranks: 2 rod(s) in 1 system(s)', 'one system')
        plan = plan_of(cantilever('', ''), 1)
        CHECK_CONTAINS(plan, 'joints: none (skipped)', 'no joints')
        CHECK_CONTAINS(plan, 'end plates: none (skipped)', 'no plates')
        CHECK_CONTAINS(plan, 'contact: none (no &contact: no contact search)', 'no contact')
    end subroutine test_bundle_plan

    function replace(text, old, new) result(out)
        character(len=*), intent(in) :: text, old, new
        character(len=:), allocatable :: out
        integer :: at
        at = index(text, old)
        out = text(1:at - 1) // new // text(at + len(old):)
    end function replace

end module rs_test_formulations_plan

program test_formulations_plan
    use rs_test_formulations_plan, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_formulations_plan
