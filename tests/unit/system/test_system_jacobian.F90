#include "rs_assert.h"
!> The system layer's assembled step Jacobian (rs_system_rod_system, issue 22 items 1 and 5)
!> against central differences of its step residual, on parsed scenes of coupled rods:
!>   (a) two rods joined end to end by each joint kind (rigid, spherical, revolute about an
!>       oblique axis), the first clamped at its start, dynamic and quasistatic;
!>   (b) two rods between a fixed &plate at their starts and a &plate at their ends that moves
!>       and turns about an off-axis centre with a ramp, dynamic and quasistatic;
!>   (c) two crossing rods with &contact, their centrelines 0.09 apart with contact radii
!>       0.05 (in contact: the contact distance is 0.1), dynamic and quasistatic;
!>   (d) a rod clamped at its start, pressed into the ground, a sphere and a cylinder
!>       (&obstacle, issue 24) by 0.005 of its contact radius 0.05, dynamic and quasistatic;
!> for se3_pg (its tie rows, rs_se3_pg_tie, and its node access) and ph_director (the same
!> scenes: a regression of the generic layer). Quasistatic scenes are checked in their time
!> steps and in the endpoint equilibrium (set_step_problem), where the couplings act at
!> X_{n+1}.
!>
!> The Jacobian is taken at a perturbed state and unknown: X_n the initial state plus random
!> noise of 1e-3, Y the predictor from it plus noise of 1e-3, the tie multipliers random in
!> [-1, 1] (so the tie Hessians enter). The error is measured per block of rows (each rod's
!> unknowns, each tie's multipliers) relative to the largest entry of those rows, so that an
!> error in the tie rows (entries of order 1) is not hidden by the rods' stiffness rows
!> (entries up to 1e5); a failing check prints every block of rows and columns over the bound.
module rs_test_system_jacobian
    use, intrinsic :: iso_fortran_env, only: output_unit
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, error_list_t
    use rs_core_strings, only: str
    use rs_test_assert, only: run_test, assert_true, assert_equal
    use rs_test_random, only: set_random_seed, random_vector
    use rs_model_scene, only: scene_t
    use rs_io_input_file, only: parse_scene
    use rs_formulations_formulation, only: state_valid
    use rs_system_rod_system, only: rod_system_t
    use rs_test_formulation_fixture, only: dense_jacobian, fixture_t_n, fixture_h
    implicit none
    private

    public :: run_all_tests

    character(len=*), parameter :: nl = new_line('a')
    ! Noise of the state and the unknown, central-difference step (relative to max(1, |y_j|)).
    real(rk), parameter :: noise = 1.0e-3_rk, fd_step = 1.0e-6_rk
    ! Bound of the error relative to the largest entry of its rows. Measured: ties 8e-11 ..
    ! 1.3e-10, se3_pg contact up to 6.5e-10, ph_director contact up to 2.9e-9 (the stiff
    ! penalty's third derivatives in the truncation error); 1e-7 sits 35 times above the worst.
    ! Below it by 40 times and more: a tie Hessian without theta (4e-6 .. 7e-6 on se3_pg), a
    ! wrong sign in a tie Hessian block (8e-6), a missing T(psi) (1e-5), the endpoint contact
    ! tangent without its factor 2 (4e-2 .. 0.5).
    real(rk), parameter :: jacobian_tol = 1.0e-7_rk
    ! The contact block (rows of one rod, columns of the other) is at least this large
    ! relative to its rows: the rods are in contact at the perturbed state (measured 8e-2 for
    ! se3_pg, 1 for ph_director).
    real(rk), parameter :: contact_visible = 1.0e-2_rk
    ! Load time of the endpoint equilibrium of the quasistatic scenes (&time t_end).
    real(rk), parameter :: t_end = 1.0_rk

    character(len=9), parameter :: joint_kinds(3) = [character(len=9) :: 'rigid', 'spherical', &
        'revolute']

    real(rk) :: worst_error = 0.0_rk

contains

    subroutine run_all_tests()
        call set_random_seed(20260301, 6151)
        call run_test('se3_pg_joints', test_se3_pg_joints)
        call run_test('se3_pg_plates', test_se3_pg_plates)
        call run_test('se3_pg_contact', test_se3_pg_contact)
        call run_test('ph_director_joints', test_ph_director_joints)
        call run_test('ph_director_plates', test_ph_director_plates)
        call run_test('ph_director_contact', test_ph_director_contact)
        call run_test('se3_pg_obstacles', test_se3_pg_obstacles)
        call run_test('ph_director_obstacles', test_ph_director_obstacles)
        write(output_unit, '(a,es10.3)') '  worst relative error of any block: ', worst_error
    end subroutine run_all_tests

    subroutine test_se3_pg_joints()
        call check_joints('se3_pg', 4)
    end subroutine test_se3_pg_joints

    subroutine test_se3_pg_plates()
        call check_plates('se3_pg', 4)
    end subroutine test_se3_pg_plates

    subroutine test_se3_pg_contact()
        call check_contact('se3_pg', 5)
    end subroutine test_se3_pg_contact

    subroutine test_ph_director_joints()
        call check_joints('ph_director', 3)
    end subroutine test_ph_director_joints

    subroutine test_ph_director_plates()
        call check_plates('ph_director', 3)
    end subroutine test_ph_director_plates

    subroutine test_ph_director_contact()
        call check_contact('ph_director', 3)
    end subroutine test_ph_director_contact

    subroutine test_se3_pg_obstacles()
        call check_obstacles('se3_pg', 4)
    end subroutine test_se3_pg_obstacles

    subroutine test_ph_director_obstacles()
        call check_obstacles('ph_director', 4)
    end subroutine test_ph_director_obstacles

    ! ---------------------------------------------------------------------------------------
    ! Scenes

    ! &time of the step the Jacobian is taken on (fixture_t_n, fixture_h lie inside it).
    function time_text(quasistatic) result(text)
        logical, intent(in) :: quasistatic
        character(len=:), allocatable :: text
        text = '&time t_end = 1, dt = 0.05'
        if (quasistatic) text = text // ', quasistatic = .true.'
        text = text // ' /' // nl
    end function time_text

    ! A rod of formulation `name` with unequal stiffnesses and inertias (no symmetry hides a
    ! transposed block), 1 long from `start` along `direction`.
    function rod_text(rod, name, n_elements, start, direction, extra) result(text)
        character(len=*), intent(in) :: rod, name, start, direction, extra
        integer, intent(in) :: n_elements
        character(len=:), allocatable :: text
        text = "&rod name = '" // rod // "', formulation = '" // name // "', n_elements = " // &
            str(n_elements) // ', length = 1,' // nl // &
            '     start = ' // start // ', direction = ' // direction // ',' // nl // &
            '     EA = 1e4, GA1 = 8e3, GA2 = 6e3, EI1 = 50, EI2 = 40, GJ = 30,' // nl // &
            '     rhoA = 1, rhoI1 = 0.01, rhoI2 = 0.02' // extra // ' /' // nl
    end function rod_text

    ! Gravity and an end force and moment on rod `rod`: every load term enters the residual.
    function loads_text(rod) result(text)
        character(len=*), intent(in) :: rod
        character(len=:), allocatable :: text
        text = "&load rod = '" // rod // "', where = 'end', force = 0.5, -1, 0.3, " // &
            'moment = 0.1, 0.2, -0.3 /' // nl // &
            "&load where = 'gravity', acceleration = 0, 0, -9.81 /" // nl
    end function loads_text

    ! (a): 'a' along x, clamped at its start; 'b' from a's end along (0, 0.6, 0.8); a.end and
    ! b.start joined by `kind` (revolute: about (0.36, -0.64, 0.48), oblique to both rods).
    function joint_scene(name, n_elements, kind, quasistatic) result(text)
        character(len=*), intent(in) :: name, kind
        integer, intent(in) :: n_elements
        logical, intent(in) :: quasistatic
        character(len=:), allocatable :: text
        text = time_text(quasistatic) // &
            rod_text('a', name, n_elements, '0, 0, 0', '1, 0, 0', '') // &
            rod_text('b', name, n_elements, '1, 0, 0', '0, 0.6, 0.8', '') // &
            "&bc rod = 'a', end = 'start', kind = 'clamped' /" // nl // &
            "&joint rod_a = 'a', end_a = 'end', rod_b = 'b', end_b = 'start', kind = '" // &
            kind // "'"
        if (kind == 'revolute') text = text // ', axis = 0.36, -0.64, 0.48'
        text = text // ' /' // nl // loads_text('b')
    end function joint_scene

    ! (b): two parallel oblique rods, their starts on the fixed plate 'base', their ends on
    ! 'head', which moves by f(t) (0.05, -0.02, 0.1) and turns by Exp(f(t) (0.1, 0.3, -0.2))
    ! about a centre off the rods, f the ramp 0 -> 1 over [0, 1].
    function plate_scene(name, n_elements, quasistatic) result(text)
        character(len=*), intent(in) :: name
        integer, intent(in) :: n_elements
        logical, intent(in) :: quasistatic
        character(len=:), allocatable :: text
        text = time_text(quasistatic) // &
            rod_text('a', name, n_elements, '0, 0, 0', '0.6, 0, 0.8', '') // &
            rod_text('b', name, n_elements, '0, 0.3, 0', '0.6, 0, 0.8', '') // &
            "&plate name = 'base', rods = 'a', 'b', end = 'start' /" // nl // &
            "&plate name = 'head', rods = 'a', 'b', end = 'end'," // nl // &
            '       centre = 0.7, 0.1, 0.9,' // nl // &
            '       displacement = 0.05, -0.02, 0.1, rotation = 0.1, 0.3, -0.2,' // nl // &
            "       time_function = 'ramp', t_on = 0, t_off = 1 /" // nl // &
            "&load where = 'gravity', acceleration = 0, 0, -9.81 /" // nl
    end function plate_scene

    ! (c): 'a' along x at height 0.09 over 'b' along y, crossing at their middles, both clamped
    ! at their starts; contact radii 0.05, so their centrelines are 0.01 inside the contact
    ! distance. Stiffness 1e7: the contact block is a tenth of the stretching stiffness of
    ! se3_pg's elements, so that an error in it shows.
    function contact_scene(name, n_elements, quasistatic) result(text)
        character(len=*), intent(in) :: name
        integer, intent(in) :: n_elements
        logical, intent(in) :: quasistatic
        character(len=:), allocatable :: text
        text = time_text(quasistatic) // &
            rod_text('a', name, n_elements, '-0.5, 0, 0.09', '1, 0, 0', &
            ', contact_radius = 0.05') // &
            rod_text('b', name, n_elements, '0, -0.5, 0', '0, 1, 0', &
            ', contact_radius = 0.05') // &
            "&bc rod = 'a', end = 'start', kind = 'clamped' /" // nl // &
            "&bc rod = 'b', end = 'start', kind = 'clamped' /" // nl // &
            '&contact stiffness = 1e7 /' // nl // loads_text('a')
    end function contact_scene

    ! (d): 'a' along x at height 0.045 over the ground z = 0, under a ball of radius 0.05
    ! about (0.3, 0, 0.14) and a cylinder of radius 0.05 about the axis through (-0.3, 0, 0.14)
    ! along y; contact radius 0.05, so each presses it by 0.005. Clamped at its start. Without
    ! `obstacles` the same rod alone (for the obstacles' share of the residual).
    function obstacle_scene(name, n_elements, quasistatic, obstacles) result(text)
        character(len=*), intent(in) :: name
        integer, intent(in) :: n_elements
        logical, intent(in) :: quasistatic
        logical, intent(in), optional :: obstacles
        character(len=:), allocatable :: text
        text = time_text(quasistatic) // "&bc rod = 'a', end = 'start', kind = 'clamped' /" // nl
        if (present(obstacles)) then
            if (.not. obstacles) then
                text = text // rod_text('a', name, n_elements, '-0.5, 0, 0.045', '1, 0, 0', '') // &
                    loads_text('a')
                return
            end if
        end if
        text = text // rod_text('a', name, n_elements, '-0.5, 0, 0.045', '1, 0, 0', &
            ', contact_radius = 0.05') // &
            "&obstacle name = 'ground', kind = 'plane', point = 0, 0, 0, normal = 0, 0, 1, " // &
            'stiffness = 1e7 /' // nl // &
            "&obstacle name = 'ball', kind = 'sphere', point = 0.3, 0, 0.14, radius = 0.05, " // &
            'stiffness = 1e7 /' // nl // &
            "&obstacle name = 'drum', kind = 'cylinder', point = -0.3, 0, 0.14, " // &
            'normal = 0, 1, 0, radius = 0.05, stiffness = 1e7 /' // nl // loads_text('a')
    end function obstacle_scene

    ! ---------------------------------------------------------------------------------------
    ! The checks per kind of coupling

    subroutine check_obstacles(name, n_elements)
        character(len=*), intent(in) :: name
        integer, intent(in) :: n_elements
        call check_scene(name // ' obstacles, dynamic', obstacle_scene(name, n_elements, &
            .false.), .false., .false.)
        call check_scene(name // ' obstacles, quasistatic', obstacle_scene(name, n_elements, &
            .true.), .true., .false.)
        call check_obstacles_act(name, n_elements)
    end subroutine check_obstacles

    !> The obstacles are in the residual checked above: at the scene's start (the predictor
    !> from the initial state), the residual with them differs from that of the rod alone by
    !> at least contact_visible of its largest entry (each obstacle presses by a tenth of the
    !> contact radius; measured in the output).
    subroutine check_obstacles_act(name, n_elements)
        character(len=*), intent(in) :: name
        integer, intent(in) :: n_elements
        real(rk), allocatable :: x_n(:), y(:), f_with(:), f_without(:)
        real(rk) :: share
        integer :: status
        call start_residual(obstacle_scene(name, n_elements, .false.), x_n, y, f_with, status)
        CHECK_EQUAL(status, state_valid, name // ': residual with the obstacles')
        call start_residual(obstacle_scene(name, n_elements, .false., .false.), x_n, y, &
            f_without, status)
        CHECK_EQUAL(status, state_valid, name // ': residual of the rod alone')
        CHECK_EQUAL(size(f_with), size(f_without), name // ': the obstacles add no unknowns')
        if (size(f_with) /= size(f_without)) return
        share = maxval(abs(f_with - f_without)) / maxval(abs(f_with))
        write(output_unit, '(a,es9.2)') '  ' // name // ' obstacles: their share of the ' // &
            'residual ', share
        CHECK_TRUE(share >= contact_visible, name // ': the obstacles act on the rod')
    end subroutine check_obstacles_act

    !> The step residual of a scene's system at the predictor from its initial state.
    subroutine start_residual(text, x_n, y, f, status)
        character(len=*), intent(in) :: text
        real(rk), allocatable, intent(out) :: x_n(:), y(:), f(:)
        integer, intent(out) :: status
        type(scene_t) :: scene
        type(error_list_t) :: errors
        type(error_t), allocatable :: err
        type(rod_system_t) :: system
        logical :: repattern
        integer :: r
        status = -1
        allocate(x_n(0), y(0), f(0))
        call parse_scene(text, 'system_jacobian.nml', scene, errors)
        CHECK_EQUAL(errors%count, 0, 'the scene parses: ' // errors%joined())
        if (errors%count > 0) return
        call system%init(scene, [(r, r = 1, size(scene%rods))], err)
        CHECK_TRUE(.not. allocated(err), 'system init')
        if (allocated(err)) return
        deallocate(x_n, y, f)
        allocate(x_n(system%n_state()), y(system%n_unknown()), f(system%n_unknown()))
        call system%initial_state(x_n)
        call system%prepare_step(fixture_t_n, fixture_h, x_n, repattern)
        call system%predictor(fixture_t_n, fixture_h, x_n, y)
        call system%step_residual(fixture_t_n, fixture_h, x_n, y, f, status)
    end subroutine start_residual

    subroutine check_joints(name, n_elements)
        character(len=*), intent(in) :: name
        integer, intent(in) :: n_elements
        integer :: k, mode
        logical :: statics
        do k = 1, size(joint_kinds)
            do mode = 0, 1
                statics = mode == 1
                call check_scene(name // ' ' // trim(joint_kinds(k)) // ' joint' // &
                    trim(merge(', quasistatic', ', dynamic    ', statics)), &
                    joint_scene(name, n_elements, trim(joint_kinds(k)), statics), statics, .false.)
            end do
        end do
    end subroutine check_joints

    subroutine check_plates(name, n_elements)
        character(len=*), intent(in) :: name
        integer, intent(in) :: n_elements
        call check_scene(name // ' moving plate, dynamic', plate_scene(name, n_elements, &
            .false.), .false., .false.)
        call check_scene(name // ' moving plate, quasistatic', plate_scene(name, n_elements, &
            .true.), .true., .false.)
    end subroutine check_plates

    subroutine check_contact(name, n_elements)
        character(len=*), intent(in) :: name
        integer, intent(in) :: n_elements
        call check_scene(name // ' contact, dynamic', contact_scene(name, n_elements, .false.), &
            .false., .true.)
        call check_scene(name // ' contact, quasistatic', contact_scene(name, n_elements, &
            .true.), .true., .true.)
    end subroutine check_contact

    !> The scene's system: its step Jacobian checked in a time step and, if `quasistatic`, in
    !> the endpoint equilibrium too; with `in_contact`, the contact block must be there.
    subroutine check_scene(label, text, quasistatic, in_contact)
        character(len=*), intent(in) :: label, text
        logical, intent(in) :: quasistatic, in_contact
        type(scene_t) :: scene
        type(error_list_t) :: errors
        type(error_t), allocatable :: err
        type(rod_system_t) :: system
        integer :: r
        call parse_scene(text, 'system_jacobian.nml', scene, errors)
        CHECK_EQUAL(errors%count, 0, label // ': the scene parses: ' // errors%joined())
        if (errors%count > 0) return
        call system%init(scene, [(r, r = 1, size(scene%rods))], err)
        CHECK_TRUE(.not. allocated(err), label // ': system init')
        if (allocated(err)) then
            write(output_unit, '(a)') '  ' // err%describe()
            return
        end if
        CHECK_TRUE(system%has_couplings(), label // ': the rods are coupled')
        call check_step(system, label, in_contact)
        if (.not. quasistatic) return
        call system%set_step_problem(.true., t_end)
        call check_step(system, label // ', endpoint', in_contact)
    end subroutine check_scene

    !> The assembled Jacobian of the step (fixture_t_n, fixture_h) at a perturbed state and
    !> unknown against central differences of the step residual, block by block.
    subroutine check_step(system, label, in_contact)
        type(rod_system_t), intent(inout) :: system
        character(len=*), intent(in) :: label
        logical, intent(in) :: in_contact
        real(rk), allocatable :: x_n(:), y(:), values(:), dense(:, :), difference(:, :)
        real(rk), allocatable :: shake(:)
        integer, allocatable :: row_ptr(:), cols(:), lo(:), hi(:)
        character(len=32), allocatable :: names(:)
        real(rk) :: worst, outside, cross, row_scale, error
        integer :: status, i, j, row, n
        logical :: repattern, ok
        character(len=160) :: line
        n = system%n_unknown()
        allocate(x_n(system%n_state()), y(n), shake(system%n_state()))
        call system%initial_state(x_n)
        call random_number(shake)
        x_n = x_n + noise * (2.0_rk * shake - 1.0_rk)
        call system%prepare_step(fixture_t_n, fixture_h, x_n, repattern)
        call system%predictor(fixture_t_n, fixture_h, x_n, y)
        y = y + random_vector(n, noise)
        call unknown_blocks(system, lo, hi, names)
        do i = size(system%members) + 1, size(lo)
            y(lo(i):hi(i)) = random_vector(hi(i) - lo(i) + 1, 1.0_rk)
        end do
        call system%jacobian_pattern(row_ptr, cols)
        CHECK_EQUAL(size(row_ptr), n + 1, label // ': pattern rows')
        allocate(values(size(cols)))
        call system%step_jacobian(fixture_t_n, fixture_h, x_n, y, values, status)
        CHECK_EQUAL(status, state_valid, label // ': Jacobian status')
        dense = dense_jacobian(row_ptr, cols, values)
        call central_differences(system, fixture_t_n, fixture_h, x_n, y, difference, ok)
        CHECK_TRUE(ok, label // ': every residual of the differences valid')
        ! Per block of rows: the largest error in each block of columns, relative to the rows'
        ! largest entry.
        worst = 0.0_rk
        outside = 0.0_rk
        cross = 0.0_rk
        do i = 1, size(lo)
            associate (d_rows => difference(lo(i):hi(i), :), j_rows => dense(lo(i):hi(i), :))
                row_scale = max(maxval(abs(d_rows)), maxval(abs(j_rows)), tiny(1.0_rk))
                do j = 1, size(lo)
                    error = maxval(abs(j_rows(:, lo(j):hi(j)) - d_rows(:, lo(j):hi(j)))) / &
                        row_scale
                    worst = max(worst, error)
                    if (error > jacobian_tol) then
                        write(line, '(a,es10.3,a,es10.3,a,es10.3)') 'relative error ', error, &
                            '; largest |J| there ', maxval(abs(j_rows(:, lo(j):hi(j)))), &
                            ', largest |differences| ', maxval(abs(d_rows(:, lo(j):hi(j))))
                        write(output_unit, '(a)') '  ' // label // ': rows ' // trim(names(i)) &
                            // ' x columns ' // trim(names(j)) // ': ' // trim(line)
                    end if
                end do
                ! Rows of rod a (member 1), columns of rod b (member 2): only contact (or a
                ! tie's Hessian) puts entries there.
                if (i == 1 .and. size(system%members) > 1) cross = &
                    maxval(abs(j_rows(:, lo(2):hi(2)))) / row_scale
                do row = lo(i), hi(i)
                    do j = 1, n
                        if (any(cols(row_ptr(row) + 1:row_ptr(row + 1)) == j - 1)) cycle
                        outside = max(outside, abs(difference(row, j)) / row_scale)
                    end do
                end do
            end associate
        end do
        worst_error = max(worst_error, worst)
        write(output_unit, '(a,i0,a,es9.2,a,es9.2,a,es9.2)') '  ' // label // ': ', n, &
            ' unknowns; relative error ', worst, ', outside the pattern ', outside, &
            ', rods a x b block ', cross
        CHECK_TRUE(worst <= jacobian_tol, label // ': assembled Jacobian = central differences')
        CHECK_TRUE(outside <= jacobian_tol, label // ': nothing outside the pattern')
        if (in_contact) then
            CHECK_TRUE(cross >= contact_visible, label // ': the rods are in contact')
        end if
    end subroutine check_step

    !> The blocks of the unknowns, 1-based ranges lo:hi: each member's own unknowns, then each
    !> coupling block (tie multipliers), with names for the report.
    subroutine unknown_blocks(system, lo, hi, names)
        type(rod_system_t), intent(in) :: system
        integer, allocatable, intent(out) :: lo(:), hi(:)
        character(len=32), allocatable, intent(out) :: names(:)
        integer :: m, c, b, n
        n = size(system%members)
        do c = 1, size(system%couplings)
            n = n + size(system%couplings(c)%coupling%blocks)
        end do
        allocate(lo(n), hi(n), names(n))
        do m = 1, size(system%members)
            associate (place => system%layout%members(m))
                lo(m) = place%unknown_offset + 1
                hi(m) = place%unknown_offset + place%n_unknown
                names(m) = 'of rod ' // system%members(m)%name
            end associate
        end do
        n = size(system%members)
        do c = 1, size(system%couplings)
            associate (blocks => system%couplings(c)%coupling%blocks)
                do b = 1, size(blocks)
                    n = n + 1
                    lo(n) = blocks(b)%unknown_offset + 1
                    hi(n) = blocks(b)%unknown_offset + blocks(b)%size
                    names(n) = 'of tie ' // str(b) // ' (multipliers)'
                end do
            end associate
        end do
    end subroutine unknown_blocks

    !> dF/dY of the system by central differences of its step residual, column by column, with
    !> the step fd_step max(1, |y_j|); `ok` false if a residual reported an invalid state.
    subroutine central_differences(system, t_n, h, x_n, y, difference, ok)
        type(rod_system_t), intent(inout) :: system
        real(rk), intent(in) :: t_n, h, x_n(:)
        real(rk), intent(inout) :: y(:)
        real(rk), allocatable, intent(out) :: difference(:, :)
        logical, intent(out) :: ok
        real(rk), allocatable :: f_plus(:), f_minus(:)
        real(rk) :: step, y_j
        integer :: n, j, status_plus, status_minus
        n = size(y)
        allocate(difference(n, n), f_plus(n), f_minus(n))
        ok = .true.
        do j = 1, n
            y_j = y(j)
            step = fd_step * max(1.0_rk, abs(y_j))
            y(j) = y_j + step
            call system%step_residual(t_n, h, x_n, y, f_plus, status_plus)
            y(j) = y_j - step
            call system%step_residual(t_n, h, x_n, y, f_minus, status_minus)
            y(j) = y_j
            ok = ok .and. status_plus == state_valid .and. status_minus == state_valid
            difference(:, j) = (f_plus - f_minus) / (2.0_rk * step)
        end do
    end subroutine central_differences

end module rs_test_system_jacobian

program test_system_jacobian
    use rs_test_system_jacobian, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_system_jacobian
