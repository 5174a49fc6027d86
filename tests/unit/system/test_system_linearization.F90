#include "rs_assert.h"
!> The linearized equations of motion read from the step Jacobians (rs_system_linearization,
!> docs/theory/modes.md), on parsed scenes, without PETSc:
!>   (a) se3_pg (second order): the pencil gives back the system's step Jacobian at a sixth
!>       step, J(h) = (2 a2 / h^2 + a1 / h + a0 / 2) / 2 (rows doubled), row by row;
!>   (b) ph_director (first order) and se3_pg on a free rod: a0 applied to a rigid translation
!>       of the nodes (the state's layout: positions moved, everything else still) vanishes,
!>       and a1 (B) or a2 (M) applied to it does not (a translation has inertia);
!>   (c) the refusals: a state in motion, se3_strand under a dead load (its dF/dX_n couples
!>       every node to the segments before it); se3_strand's one-step pencil (modal_one_step,
!>       dF/dY + dF/dX_n): first order with simple zeros, a steady rigid translation of a free
!>       rod (momenta rho A v at every node, no stress) in the null space of a0 = A and not of
!>       a1 = B;
!>   (d) buckling_stiffness of a quasistatic ph_director rod (the Jacobian of its static
!>       problem, traits static_tangent): a rigid translation is in the null space of K_T at
!>       the reference, the system is back in time steps after it, and a dynamic ph_director
!>       rod (a first-order pencil, no static problem) is refused;
!>   (e) equilibrate (the eigen solve's scaling) on a damped ph_director and a se3_pg pencil,
!>       whose rows' largest entries lie orders of magnitude apart: factors that are powers of
!>       2, every row's and column's largest entry of the scaled magnitude within a factor 2
!>       of 1, and the same scaling for a weight that differs in its last bits.
module rs_test_system_linearization
    use rs_core_kinds, only: rk
    use rs_test_singular_values, only: singular_values
    use rs_core_error, only: error_t, error_list_t
    use rs_core_strings, only: str, str_significant
    use rs_test_assert, only: run_test, assert_true, assert_equal, assert_contains
    use rs_model_scene, only: scene_t
    use rs_io_input_file, only: parse_scene
    use rs_formulations_formulation, only: state_valid, modal_first_order, modal_second_order
    use rs_system_rod_system, only: rod_system_t
    use rs_system_linearization, only: pencil_t, linearize_system, buckling_stiffness, &
        equilibrate
    implicit none
    private


    public :: run_all_tests

    character(len=*), parameter :: nl = new_line('a')
    !> The step of the scenes; the pencil is read about t = 0.
    real(rk), parameter :: dt = 1.0e-4_rk

contains

    subroutine run_all_tests()
        call run_test('se3_pg_reconstructs_jacobian', test_se3_pg_reconstructs_jacobian)
        call run_test('ph_director_translation', test_ph_director_translation)
        call run_test('se3_pg_translation', test_se3_pg_translation)
        call run_test('refusals', test_refusals)
        call run_test('se3_strand_rigid_motion', test_se3_strand_rigid_motion)
        call run_test('ph_director_static_tangent', test_ph_director_static_tangent)
        call run_test('ph_director_equilibrate', test_ph_director_equilibrate)
        call run_test('se3_pg_equilibrate', test_se3_pg_equilibrate)
    end subroutine run_all_tests

    !> A steel rod of `n` elements along x, clamped at its start unless `free`; a quasistatic
    !> run with `quasistatic`.
    function scene_text(formulation, n, free, extra, quasistatic) result(text)
        character(len=*), intent(in) :: formulation, extra
        integer, intent(in) :: n
        logical, intent(in) :: free
        logical, intent(in), optional :: quasistatic
        character(len=:), allocatable :: text
        text = '&time t_end = 1e-4, dt = 1e-4 /' // nl
        if (present(quasistatic)) then
            if (quasistatic) text = '&time t_end = 1, dt = 0.5, quasistatic = .true. /' // nl
        end if
        text = text // &
            "&rod name = 'beam', formulation = '" // formulation // "', n_elements = " // &
            str(n) // ', length = 1,' // nl // &
            '     start = 0, 0, 0, direction = 1, 0, 0,' // nl // &
            "     section = 'circle', radius = 0.01, E = 2e11, G = 8e10, density = 7800" // &
            extra // ' /' // nl
        if (.not. free) text = text // "&bc rod = 'beam', end = 'start', kind = 'clamped' /" // nl
    end function scene_text

    subroutine build(text, system, x)
        character(len=*), intent(in) :: text
        type(rod_system_t), intent(out) :: system
        real(rk), allocatable, intent(out) :: x(:)
        type(scene_t) :: scene
        type(error_list_t) :: errors
        type(error_t), allocatable :: err
        call parse_scene(text, 'linearization.nml', scene, errors)
        CHECK_EQUAL(errors%count, 0, 'the scene parses: ' // errors%joined())
        call system%init(scene, [1], err)
        CHECK_TRUE(.not. allocated(err), 'the system builds')
        allocate(x(system%n_state()))
        call system%initial_state(x)
    end subroutine build

    subroutine test_se3_pg_reconstructs_jacobian()
        type(rod_system_t) :: system
        type(pencil_t) :: pencil
        type(error_t), allocatable :: err
        real(rk), allocatable :: x(:), y(:), values(:), rebuilt(:)
        real(rk) :: h, worst, scale
        character(len=:), allocatable :: message
        integer :: status, i, lo, hi
        call build(scene_text('se3_pg', 12, .false., ''), system, x)
        call linearize_system(system, 0.0_rk, x, dt, pencil, err)
        CHECK_TRUE(.not. allocated(err), 'se3_pg linearizes')
        if (allocated(err)) return
        CHECK_EQUAL(pencil%form, modal_second_order, 'se3_pg: second order')
        CHECK_EQUAL(pencil%n_algebraic, 0, 'se3_pg cantilever: no algebraic rows')
        CHECK_TRUE(all(pencil%a1 == 0.0_rk), 'se3_pg undamped: a1 = 0 exactly')
        ! A step unlike the fit's, with the forces at t = 0.
        h = 0.37_rk * dt
        allocate(y(pencil%n), values(size(pencil%cols)))
        call system%predictor(-0.5_rk * h, h, x, y)
        call system%step_jacobian(-0.5_rk * h, h, x, y, values, status)
        CHECK_EQUAL(status, state_valid, 'the Jacobian at the sixth step')
        rebuilt = 0.5_rk * (2.0_rk * pencil%a2 / h**2 + pencil%a1 / h + 0.5_rk * pencil%a0)
        worst = 0.0_rk
        do i = 1, pencil%n
            lo = pencil%row_ptr(i) + 1
            hi = pencil%row_ptr(i + 1)
            scale = maxval(abs(values(lo:hi)))
            worst = max(worst, maxval(abs(rebuilt(lo:hi) - values(lo:hi))) / scale)
        end do
        ! Measured 4.4e-16 (round-off of the refined coefficients).
        message = 'the pencil gives back J(h) row by row (relative error ' // str_significant(worst, 3) // ')'
        CHECK_TRUE(worst < 1.0e-12_rk, message)
    end subroutine test_se3_pg_reconstructs_jacobian

    subroutine test_ph_director_translation()
        call check_translation('ph_director', modal_first_order)
    end subroutine test_ph_director_translation

    subroutine test_se3_pg_translation()
        call check_translation('se3_pg', modal_second_order)
    end subroutine test_se3_pg_translation

    !> On a free rod, a rigid translation t of the nodes (in the step unknowns' layout) is in
    !> the null space of a0 to round-off, and has inertia (a1 t, or a2 t, not zero).
    subroutine check_translation(formulation, form)
        character(len=*), intent(in) :: formulation
        integer, intent(in) :: form
        type(rod_system_t) :: system
        type(pencil_t) :: pencil
        type(error_t), allocatable :: err
        real(rk), allocatable :: x(:), t(:), a0t(:), inertia(:)
        real(rk) :: bound
        character(len=:), allocatable :: message
        integer :: k, m, i
        call build(scene_text(formulation, 6, .true., ''), system, x)
        call linearize_system(system, 0.0_rk, x, dt, pencil, err)
        CHECK_TRUE(.not. allocated(err), formulation // ' linearizes')
        if (allocated(err)) return
        CHECK_EQUAL(pencil%form, form, formulation // ': the declared form')
        allocate(t(pencil%n), source=0.0_rk)
        m = 1
        associate (nodes => system%layout%members(m)%nodes, &
                uo => system%layout%members(m)%unknown_offset)
            do k = 1, nodes%n_nodes
                do i = 1, 3
                    if (nodes%unknown(i, k) > 0) t(uo + nodes%unknown(i, k)) = &
                        real(i, rk) / 3.0_rk
                end do
            end do
        end associate
        a0t = csr_times(pencil, pencil%a0, t)
        inertia = csr_times(pencil, merge(pencil%a1, pencil%a2, form == modal_first_order), t)
        ! Measured |a0 t| = 1.9e-16 (ph_director) and 6e-8 (se3_pg, whose a0 reaches 1e10).
        bound = 1.0e-12_rk * maxval(abs(pencil%a0)) * maxval(abs(t))
        message = formulation // ': a rigid translation is in the null space of a0 (|a0 t| = ' // &
            str_significant(maxval(abs(a0t)), 3) // ')'
        CHECK_TRUE(maxval(abs(a0t)) <= bound, message)
        message = formulation // ': a rigid translation has inertia'
        CHECK_TRUE(maxval(abs(inertia)) > 1.0e-6_rk * maxval(abs(t)), message)
    end subroutine check_translation

    subroutine test_refusals()
        type(rod_system_t) :: system
        type(pencil_t) :: pencil
        type(error_t), allocatable :: err
        real(rk), allocatable :: x(:)
        call build(scene_text('se3_strand', 6, .false., " /" // nl // &
            "&load rod = 'beam', where = 'gravity', acceleration = 0, 0, -9.81"), system, x)
        call linearize_system(system, 0.0_rk, x, dt, pencil, err)
        CHECK_TRUE(allocated(err), 'se3_strand under a dead load is refused')
        if (allocated(err)) CHECK_CONTAINS(err%message, 'by the state at t_n', 'the refusal says why')
        call build(scene_text('se3_pg', 6, .true., ', velocity = 0, 1, 0'), system, x)
        call linearize_system(system, 0.0_rk, x, dt, pencil, err)
        CHECK_TRUE(allocated(err), 'a state in motion is refused')
        if (allocated(err)) CHECK_CONTAINS(err%message, 'not at rest', 'the refusal says why')
    end subroutine test_refusals

    !> se3_strand's pencil (modal_one_step) on a free rod: first order, its rigid motions simple
    !> zeros; the unknowns are blocks of 6 (block 0 the ghost stress, 2k + 1 the momentum P_k
    !> of node k, 2k + 2 the stress of segment k; methods/se3_strands.md §3.5), the linear
    !> momentum in components 4..6. A steady translation, P_k = rho A (v, v, v) and no stress,
    !> makes A vanish to round-off and B not (it is the rate of a momentum).
    subroutine test_se3_strand_rigid_motion()
        type(rod_system_t) :: system
        type(pencil_t) :: pencil
        type(error_t), allocatable :: err
        real(rk), allocatable :: x(:), t(:), a0t(:), a1t(:), s(:), a(:, :), row_scale(:), &
            col_scale(:)
        real(rk), parameter :: rho_a = 7800.0_rk * 3.141592653589793_rk * 1.0e-4_rk
        character(len=:), allocatable :: message
        integer :: k, n_segments, i, info
        n_segments = 6
        call build(scene_text('se3_strand', n_segments, .true., ''), system, x)
        call linearize_system(system, 0.0_rk, x, dt, pencil, err)
        CHECK_TRUE(.not. allocated(err), 'se3_strand linearizes')
        if (allocated(err)) return
        CHECK_EQUAL(pencil%form, modal_first_order, 'se3_strand: a first-order pencil')
        CHECK_TRUE(pencil%simple_zeros, 'se3_strand: rigid motions are simple zeros')
        allocate(t(pencil%n), source=0.0_rk)
        do k = 0, n_segments
            t(6 * (2 * k + 1) + 4:6 * (2 * k + 1) + 6) = rho_a
        end do
        a0t = csr_times(pencil, pencil%a0, t)
        a1t = csr_times(pencil, pencil%a1, t)
        ! Exact cancellations: measured 0 against |a0| |t| of about 1e7.
        message = 'se3_strand: a steady translation is in the null space of A (|A t| = ' // &
            str_significant(maxval(abs(a0t)), 3) // ')'
        CHECK_TRUE(maxval(abs(a0t)) <= 1.0e-12_rk * maxval(abs(pencil%a0)) * maxval(abs(t)), message)
        CHECK_TRUE(maxval(abs(a1t)) > 1.0e-6_rk * maxval(abs(t)), 'se3_strand: B t /= 0')
        ! All six steady rigid motions, the rotations too, and nothing else: A (dense, 90 x 90,
        ! equilibrated as the eigen solve does, by powers of 2) has exactly six zero singular
        ! values. Measured: six up to 1.4e-16 of the largest, the seventh at 2.5e-2. (A read
        ! from dF/dY alone as a midpoint step has the same null space; that error shows in the
        ! frequencies, tests/regression/modes/strand_modes.py.)
        allocate(row_scale(pencil%n), col_scale(pencil%n))
        call equilibrate(pencil, 1.0e3_rk, row_scale, col_scale)
        a = dense(pencil, pencil%a0)
        do i = 1, pencil%n
            a(i, :) = row_scale(i) * a(i, :) * col_scale
        end do
        s = singular_values(a, info)
        CHECK_EQUAL(info, 0, 'dgesvd')
        message = 'se3_strand: A of a free rod has six zero singular values (the smallest ' // &
            'seven over the largest: ' // str_significant(s(size(s) - 6) / s(1), 3) // ', ' // &
            str_significant(s(size(s) - 5) / s(1), 3) // ' ...)'
        CHECK_TRUE(s(size(s) - 5) <= 1.0e-14_rk * s(1) .and. s(size(s) - 6) > 1.0e-4_rk * s(1), message)
    end subroutine test_se3_strand_rigid_motion

    !> The CSR values `values` of `pencil`'s pattern as a dense matrix.
    function dense(pencil, values) result(a)
        type(pencil_t), intent(in) :: pencil
        real(rk), intent(in) :: values(:)
        real(rk) :: a(pencil%n, pencil%n)
        integer :: i, k
        a = 0.0_rk
        do i = 1, pencil%n
            do k = pencil%row_ptr(i) + 1, pencil%row_ptr(i + 1)
                a(i, pencil%cols(k) + 1) = values(k)
            end do
        end do
    end function dense


    !> buckling_stiffness of a free quasistatic ph_director rod about its reference: both
    !> stiffnesses read from the static problem (no mass: a1 = a2 = 0), a rigid translation of
    !> the nodes in the null space of K_T (the strains do not change; no stress or multiplier
    !> at the reference), the unbalance zero; the system in time steps again. A dynamic
    !> ph_director rod has no static problem and a first-order pencil: refused.
    subroutine test_ph_director_static_tangent()
        type(rod_system_t) :: system
        type(pencil_t) :: reference, loaded
        type(error_t), allocatable :: err
        real(rk), allocatable :: x(:), t(:), kt(:)
        character(len=:), allocatable :: message
        integer :: k, i
        call build(scene_text('ph_director', 4, .true., '', quasistatic=.true.), system, x)
        call buckling_stiffness(system, 1.0_rk, x, 0.5_rk, reference, loaded, err)
        CHECK_TRUE(.not. allocated(err), 'the static tangent of a quasistatic ph_director rod')
        if (allocated(err)) return
        CHECK_TRUE(reference%stiffness .and. loaded%stiffness, 'both are stiffnesses')
        CHECK_TRUE(all(reference%a1 == 0.0_rk) .and. all(reference%a2 == 0.0_rk), 'no mass terms')
        CHECK_TRUE(.not. system%static, 'the system is in time steps again')
        CHECK_TRUE(loaded%unbalance <= 1.0e-14_rk, 'the unloaded reference is in equilibrium')
        allocate(t(reference%n), source=0.0_rk)
        associate (nodes => system%layout%members(1)%nodes)
            do k = 1, nodes%n_nodes
                do i = 1, 3
                    if (nodes%unknown(i, k) > 0) t(nodes%unknown(i, k)) = real(i, rk) / 3.0_rk
                end do
            end do
        end associate
        kt = csr_times(reference, reference%a0, t)
        message = 'ph_director: a rigid translation is in the null space of K_T (|K_T t| = ' // &
            str_significant(maxval(abs(kt)), 3) // ')'
        CHECK_TRUE(maxval(abs(kt)) <= 1.0e-12_rk * maxval(abs(reference%a0)), message)
        call build(scene_text('ph_director', 4, .false., ''), system, x)
        call buckling_stiffness(system, 0.0_rk, x, dt, reference, loaded, err)
        CHECK_TRUE(allocated(err), 'a dynamic ph_director rod is refused')
        if (allocated(err)) CHECK_CONTAINS(err%message, 'not available for ph_director', 'named')
    end subroutine test_ph_director_static_tangent

    function csr_times(pencil, values, v) result(w)
        type(pencil_t), intent(in) :: pencil
        real(rk), intent(in) :: values(:), v(:)
        real(rk) :: w(pencil%n)
        integer :: i, p
        w = 0.0_rk
        do i = 1, pencil%n
            do p = pencil%row_ptr(i) + 1, pencil%row_ptr(i + 1)
                w(i) = w(i) + values(p) * v(pencil%cols(p) + 1)
            end do
        end do
    end function csr_times

    subroutine test_ph_director_equilibrate()
        call check_equilibrate('ph_director', ', kelvin_voigt_time = 1e-4', 1.0e3_rk)
    end subroutine test_ph_director_equilibrate

    subroutine test_se3_pg_equilibrate()
        call check_equilibrate('se3_pg', '', 1.0e3_rk)
    end subroutine test_se3_pg_equilibrate

    !> equilibrate on the clamped rod's pencil at the frequency `weight` (module header, (e)).
    subroutine check_equilibrate(formulation, extra, weight)
        character(len=*), intent(in) :: formulation, extra
        real(rk), intent(in) :: weight
        type(rod_system_t) :: system
        type(pencil_t) :: pencil
        type(error_t), allocatable :: err
        real(rk), allocatable :: x(:), rows(:), cols(:), again_rows(:), again_cols(:)
        real(rk), allocatable :: before(:), row_max(:), col_max(:)
        real(rk) :: w, v, spread
        character(len=:), allocatable :: message
        logical :: ok
        integer :: i, j, k
        call build(scene_text(formulation, 8, .false., extra), system, x)
        call linearize_system(system, 0.0_rk, x, dt, pencil, err)
        CHECK_TRUE(.not. allocated(err), formulation // ' linearizes')
        if (allocated(err)) return
        allocate(rows(pencil%n), cols(pencil%n), again_rows(pencil%n), again_cols(pencil%n))
        call equilibrate(pencil, weight, rows, cols)
        ok = all(fraction(rows) == 0.5_rk) .and. all(fraction(cols) == 0.5_rk)
        CHECK_TRUE(ok, formulation // ': every factor is a power of 2')
        ! The weight is used as the nearest power of 2 (1024 for 1e3).
        w = 1024.0_rk
        allocate(before(pencil%n), row_max(pencil%n), col_max(pencil%n), source=0.0_rk)
        do i = 1, pencil%n
            do k = pencil%row_ptr(i) + 1, pencil%row_ptr(i + 1)
                j = pencil%cols(k) + 1
                v = abs(pencil%a0(k)) + w * abs(pencil%a1(k)) + w**2 * abs(pencil%a2(k))
                before(i) = max(before(i), v)
                row_max(i) = max(row_max(i), rows(i) * v * cols(j))
                col_max(j) = max(col_max(j), rows(i) * v * cols(j))
            end do
        end do
        spread = maxval(before) / minval(before, mask=before > 0.0_rk)
        ! Measured 5.5e8 (damped ph_director: a row of stiffness and damping next to a kinematic
        ! identity) and 1.0e5 (se3_pg).
        message = formulation // ': the pencil''s rows are not balanced (their largest ' // &
            'entries ' // str_significant(spread, 3) // ' apart)'
        CHECK_TRUE(spread > 1.0e4_rk, message)
        message = formulation // ': every row''s and column''s largest scaled entry in ' // &
            '[1/2, 2] (' // str_significant(min(minval(row_max), minval(col_max)), 3) // ' .. ' // &
            str_significant(max(maxval(row_max), maxval(col_max)), 3) // ')'
        ok = all(row_max >= 0.5_rk .and. row_max <= 2.0_rk) .and. &
            all(col_max >= 0.5_rk .and. col_max <= 2.0_rk)
        CHECK_TRUE(ok, message)
        call equilibrate(pencil, weight * (1.0_rk + 1.0e-12_rk), again_rows, again_cols)
        ok = all(again_rows == rows) .and. all(again_cols == cols)
        CHECK_TRUE(ok, formulation // ': a weight differing in its last bits scales alike')
    end subroutine check_equilibrate

end module rs_test_system_linearization

program test_system_linearization
    use rs_test_system_linearization, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_system_linearization
