#include "rs_assert.h"
!> Unit tests of rs_solver_rod_stepper (src/solver/rod_stepper.f90, rod_stepper.c, rodmid.c and
!> the options of petsc_init.c) on toy step problems whose callbacks are the `bind(C)`
!> procedures of this module:
!> - harmonic oscillator, implicit midpoint with X = Y = (q, v): energy kept to 1e-13 relative
!>   over 1000 steps, observed order 2 against cos/sin;
!> - the same oscillator with Y = q_{n+1} only (v eliminated, own predictor and update): the
!>   same solution as the full layout;
!> - pendulum in Cartesian coordinates with a multiplier and |x_{n+1}|^2 = 1 imposed at the
!>   endpoint (a saddle point: zero diagonal for the multiplier), solved with MUMPS: several
!>   Newton iterations per step, fnorm < 1e-12, constraint to 1e-14, energy to a multiple of
!>   the Newton residuals, one symbolic factorization for the whole run (PETSc's event count);
!> - cut-back: a residual that reports an invalid state for h > 0.03 makes the stepper halve
!>   (exact counts follow from "try the rest of dt, halve on failure") and the answer equals
!>   taking the same small steps directly; with max_cutbacks = 2 and an invalid region after
!>   t = 0.05 the advance fails with the message and x is the last good state;
!> - the pendulum with a kept Jacobian (&solver jacobian_reuse = 0.1): converged steps, the
!>   constraint to atol, energy to the residuals, Newton's state to 200 x atol, fewer than half
!>   as many factorizations as iterations (908 iterations, 198 Jacobians when written); the
!>   cut-back case gives the same halvings as Newton's method;
!> - options precedence: scene values < petsc_options < command line. The command line is
!>   real: the program passes `-snes_max_funcs 3000` (and its own arguments) to PetscInitialize;
!> - TSView's rodmid line, argument checks, a fatal callback status, and PETSc's native LU
!>   failing on the saddle point where MUMPS succeeds (the error text reaches Fortran);
!> - the traits struct (stepper_traits_t = struct rs_stepper_traits): every field, each set to
!>   a value no other field has, is found in the SNES, the line search, the LU package and
!>   ordering and the rodmid line that PETSc reports back.
module rs_test_solver_rod_stepper
    use, intrinsic :: iso_c_binding, only: c_int, c_double, c_ptr, c_funptr, c_null_funptr, &
        c_funloc, c_loc, c_f_pointer
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t
    use rs_test_assert, only: run_test, assert_true, assert_close, assert_equal, assert_contains
    use rs_solver_rod_stepper, only: rod_stepper_t, stepper_traits_t, petsc_apply_options, &
        petsc_options_text, petsc_event_count
    implicit none
    private

    public :: run_all_tests

    integer, parameter :: oscillator = 1, oscillator_reduced = 2, pendulum = 3
    integer, parameter :: max_records = 64
    real(rk), parameter :: gravity = 9.81_rk
    real(rk), parameter :: atol = 1.0e-12_rk

    !> What the callbacks see: the problem, its invalid region and what the poststep records.
    type :: problem_t
        integer :: kind = oscillator
        integer :: n_state = 2
        integer :: n_unknown = 2
        real(rk) :: omega = 1.0_rk
        !> The residual reports an invalid state for h > h_limit or t_n + h > t_limit.
        real(rk) :: h_limit = huge(1.0_rk)
        real(rk) :: t_limit = huge(1.0_rk)
        !> Non-zero: the residual returns this status (a fatal one).
        integer :: fatal_status = 0
        integer :: n_predictor = 0
        integer :: n_update = 0
        integer :: n_post = 0
        real(rk) :: t_taken(max_records) = 0.0_rk
        real(rk) :: h_taken(max_records) = 0.0_rk
        integer :: newton_its = 0
        real(rk) :: max_fnorm = 0.0_rk
        real(rk) :: sum_fnorm = 0.0_rk
        real(rk) :: max_constraint = 0.0_rk
    end type problem_t

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('oscillator_energy_1000_steps', test_oscillator_energy)
        call run_test('oscillator_order_2', test_oscillator_order)
        call run_test('reduced_unknowns_predictor_update', test_reduced_unknowns)
        call run_test('pendulum_saddle_point_mumps', test_pendulum)
        call run_test('pendulum_jacobian_reuse', test_pendulum_reuse)
        call run_test('cutback_same_answer_as_small_steps', test_cutback_succeeds)
        call run_test('cutback_with_jacobian_reuse', test_cutback_reuse)
        call run_test('cutback_exhausted_keeps_last_good_state', test_cutback_fails)
        call run_test('options_precedence', test_options_precedence)
        call run_test('view_names_rodmid', test_view)
        call run_test('traits_reach_the_solver', test_traits_reach_the_solver)
        call run_test('bad_pattern_rejected', test_bad_pattern)
        call run_test('bordered_solves', test_bordered_solves)
        ! Last: these end in PETSc errors (printed with PETSc's trace).
        call run_test('fatal_callback_status', test_fatal_callback)
        call run_test('native_lu_fails_on_saddle_point', test_native_lu_fails)
    end subroutine run_all_tests

    ! ---- Problems -----------------------------------------------------------------------------

    !> A problem of `kind` with its sizes.
    function new_problem(kind) result(problem)
        integer, intent(in) :: kind
        type(problem_t) :: problem
        problem%kind = kind
        select case (kind)
        case (oscillator)
            problem%n_state = 2
            problem%n_unknown = 2
        case (oscillator_reduced)
            problem%n_state = 2
            problem%n_unknown = 1
        case (pendulum)
            problem%n_state = 4
            problem%n_unknown = 5
        end select
    end function new_problem

    !> Create the stepper of `problem` with the test defaults (atol 1e-12, rtol 0, 25
    !> iterations) and `max_cutbacks`.
    subroutine create_stepper(stepper, problem, max_cutbacks, err, max_newton, jacobian_reuse)
        type(rod_stepper_t), intent(inout) :: stepper
        type(problem_t), target, intent(inout) :: problem
        integer, intent(in) :: max_cutbacks
        type(error_t), allocatable, intent(out) :: err
        integer, intent(in), optional :: max_newton
        real(rk), intent(in), optional :: jacobian_reuse
        integer, allocatable :: row_ptr(:), cols(:)
        type(c_funptr) :: residual, jacobian, predictor, update
        type(stepper_traits_t) :: traits
        integer :: its
        its = 25
        if (present(max_newton)) its = max_newton
        predictor = c_null_funptr
        update = c_null_funptr
        select case (problem%kind)
        case (oscillator)
            row_ptr = [0, 2, 4]
            cols = [0, 1, 0, 1]
            residual = c_funloc(oscillator_residual)
            jacobian = c_funloc(oscillator_jacobian)
        case (oscillator_reduced)
            row_ptr = [0, 1]
            cols = [0]
            residual = c_funloc(reduced_residual)
            jacobian = c_funloc(reduced_jacobian)
            predictor = c_funloc(reduced_predictor)
            update = c_funloc(reduced_update)
        case default
            ! No (4, 4) entry: the multiplier's diagonal is structurally zero.
            row_ptr = [0, 2, 4, 7, 10, 12]
            cols = [0, 2, 1, 3, 0, 2, 4, 1, 3, 4, 0, 1]
            residual = c_funloc(pendulum_residual)
            jacobian = c_funloc(pendulum_jacobian)
            predictor = c_funloc(pendulum_predictor)
            update = c_funloc(pendulum_update)
        end select
        traits = stepper_traits_t(newton_atol=atol, newton_rtol=0.0_rk, max_newton=its, &
            max_cutbacks=max_cutbacks)
        if (present(jacobian_reuse)) traits%jacobian_reuse = jacobian_reuse
        call stepper%create(problem%n_state, problem%n_unknown, row_ptr, cols, residual, &
            jacobian, predictor, update, c_funloc(record_poststep), c_loc(problem), traits, err)
    end subroutine create_stepper

    !> The bordered solves of arc-length continuation (rs_stepper_factor, rs_stepper_solve) on
    !> the pendulum's saddle-point pattern (a zero multiplier diagonal): two right-hand sides
    !> with one factorization, each J sol = rhs to 1e-13 (the residual computed here from the
    !> CSR values), a second factorization of other values used by the next solve, and a
    !> singular matrix (a zero row) reported as singular or as an error, not as a solution.
    subroutine test_bordered_solves()
        type(problem_t), target :: problem
        type(rod_stepper_t) :: stepper
        type(error_t), allocatable :: err
        integer, parameter :: row_ptr(6) = [0, 2, 4, 7, 10, 12]
        integer, parameter :: cols(12) = [0, 2, 1, 3, 0, 2, 4, 1, 3, 4, 0, 1]
        real(rk) :: values(12), rhs(5, 2), sol(5)
        logical :: singular, failed
        integer :: k
        problem = new_problem(pendulum)
        call create_stepper(stepper, problem, 6, err)
        if (allocated(err)) then
            CHECK_TRUE(.false., 'create: ' // err%message)
            return
        end if
        values = [2.0_rk, -0.5_rk, 3.0_rk, 0.25_rk, 0.5_rk, 4.0_rk, 1.0_rk, -1.0_rk, 5.0_rk, &
            0.7_rk, 1.0_rk, 0.7_rk]
        rhs(:, 1) = [1.0_rk, -2.0_rk, 0.5_rk, 3.0_rk, -1.0_rk]
        rhs(:, 2) = [0.0_rk, 1.0_rk, 0.0_rk, -1.0_rk, 2.0_rk]
        call stepper%factor(values, singular, err)
        CHECK_TRUE(.not. allocated(err), 'the factorization runs')
        CHECK_TRUE(.not. singular, 'a regular saddle-point matrix is not singular')
        if (allocated(err) .or. singular) return
        do k = 1, 2
            call stepper%solve(rhs(:, k), sol, failed, err)
            CHECK_TRUE(.not. allocated(err) .and. .not. failed, 'each right-hand side solves')
            CHECK_TRUE(maxval(abs(csr_times(values, sol) - rhs(:, k))) <= 1.0e-13_rk, 'J sol = rhs for each right-hand side')
        end do
        values(1:2) = 2.0_rk * values(1:2)
        call stepper%factor(values, singular, err)
        call stepper%solve(rhs(:, 1), sol, failed, err)
        CHECK_TRUE(.not. allocated(err) .and. .not. failed, 'solve after a new factorization')
        CHECK_TRUE(maxval(abs(csr_times(values, sol) - rhs(:, 1))) <= 1.0e-13_rk, 'J sol = rhs with the new values')
        values(3:4) = 0.0_rk
        call stepper%factor(values, singular, err)
        CHECK_TRUE(singular .or. allocated(err), 'a zero row: singular, or an error')
        call stepper%destroy()
    contains
        function csr_times(a, v) result(w)
            real(rk), intent(in) :: a(:), v(:)
            real(rk) :: w(5)
            integer :: i, p
            w = 0.0_rk
            do i = 1, 5
                do p = row_ptr(i) + 1, row_ptr(i + 1)
                    w(i) = w(i) + a(p) * v(cols(p) + 1)
                end do
            end do
        end function csr_times
    end subroutine test_bordered_solves

    !> Midpoint rule for q' = v, v' = -omega^2 q: F = (q1 - q0 - h vm, v1 - v0 + h omega^2 qm).
    function oscillator_residual(ctx, t_n, h, x_n, y, f) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y, f
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        type(problem_t), pointer :: p
        real(rk), pointer :: x0(:), y1(:), r(:)
        call c_f_pointer(ctx, p)
        status = check_state(p, t_n, h)
        if (status /= 0) return
        call c_f_pointer(x_n, x0, [2])
        call c_f_pointer(y, y1, [2])
        call c_f_pointer(f, r, [2])
        r(1) = y1(1) - x0(1) - 0.5_rk * h * (x0(2) + y1(2))
        r(2) = y1(2) - x0(2) + 0.5_rk * h * p%omega**2 * (x0(1) + y1(1))
    end function oscillator_residual

    function oscillator_jacobian(ctx, t_n, h, x_n, y, values) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y, values
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        type(problem_t), pointer :: p
        real(rk), pointer :: v(:)
        call c_f_pointer(ctx, p)
        call c_f_pointer(values, v, [4])
        v = [1.0_rk, -0.5_rk * h, 0.5_rk * h * p%omega**2, 1.0_rk]
        status = 0
    end function oscillator_jacobian

    !> The oscillator with v eliminated: v1 = 2 (q1 - q0) / h - v0, so the velocity equation
    !> times h/2 reads (q1 - q0) - h v0 + h^2 omega^2 (q0 + q1) / 4 = 0 for Y = q1.
    function reduced_residual(ctx, t_n, h, x_n, y, f) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y, f
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        type(problem_t), pointer :: p
        real(rk), pointer :: x0(:), y1(:), r(:)
        call c_f_pointer(ctx, p)
        status = check_state(p, t_n, h)
        if (status /= 0) return
        call c_f_pointer(x_n, x0, [2])
        call c_f_pointer(y, y1, [1])
        call c_f_pointer(f, r, [1])
        r(1) = y1(1) - x0(1) - h * x0(2) + 0.25_rk * h**2 * p%omega**2 * (x0(1) + y1(1))
    end function reduced_residual

    function reduced_jacobian(ctx, t_n, h, x_n, y, values) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y, values
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        type(problem_t), pointer :: p
        real(rk), pointer :: v(:)
        call c_f_pointer(ctx, p)
        call c_f_pointer(values, v, [1])
        v(1) = 1.0_rk + 0.25_rk * h**2 * p%omega**2
        status = 0
    end function reduced_jacobian

    !> Explicit Euler for q: a predictor that differs from the default.
    function reduced_predictor(ctx, t_n, h, x_n, y) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        type(problem_t), pointer :: p
        real(rk), pointer :: x0(:), y1(:)
        call c_f_pointer(ctx, p)
        call c_f_pointer(x_n, x0, [2])
        call c_f_pointer(y, y1, [1])
        y1(1) = x0(1) + h * x0(2)
        p%n_predictor = p%n_predictor + 1
        status = 0
    end function reduced_predictor

    function reduced_update(ctx, t_n, h, x_n, y, x_np1) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y, x_np1
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        type(problem_t), pointer :: p
        real(rk), pointer :: x0(:), y1(:), x1(:)
        call c_f_pointer(ctx, p)
        call c_f_pointer(x_n, x0, [2])
        call c_f_pointer(y, y1, [1])
        call c_f_pointer(x_np1, x1, [2])
        x1(1) = y1(1)
        x1(2) = 2.0_rk * (y1(1) - x0(1)) / h - x0(2)
        p%n_update = p%n_update + 1
        status = 0
    end function reduced_update

    !> Pendulum of unit length and mass, X = (x, v), Y = (x1, v1, lambda):
    !>   x1 - x0 - h (v0 + v1)/2 = 0,  v1 - v0 - h g + lambda (x0 + x1)/2 = 0,  (|x1|^2 - 1)/2 = 0,
    !> with g = (0, -9.81). The constraint force uses the midpoint gradient, which is the
    !> discrete gradient of |x|^2: energy is kept when both ends lie on the circle.
    function pendulum_residual(ctx, t_n, h, x_n, y, f) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y, f
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        type(problem_t), pointer :: p
        real(rk), pointer :: x0(:), y1(:), r(:)
        real(rk) :: xm(2)
        call c_f_pointer(ctx, p)
        status = check_state(p, t_n, h)
        if (status /= 0) return
        call c_f_pointer(x_n, x0, [4])
        call c_f_pointer(y, y1, [5])
        call c_f_pointer(f, r, [5])
        xm = 0.5_rk * (x0(1:2) + y1(1:2))
        r(1:2) = y1(1:2) - x0(1:2) - 0.5_rk * h * (x0(3:4) + y1(3:4))
        r(3:4) = y1(3:4) - x0(3:4) - h * [0.0_rk, -gravity] + y1(5) * xm
        r(5) = 0.5_rk * (y1(1)**2 + y1(2)**2 - 1.0_rk)
    end function pendulum_residual

    function pendulum_jacobian(ctx, t_n, h, x_n, y, values) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y, values
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        real(rk), pointer :: x0(:), y1(:), v(:)
        real(rk) :: xm(2)
        call c_f_pointer(x_n, x0, [4])
        call c_f_pointer(y, y1, [5])
        call c_f_pointer(values, v, [12])
        xm = 0.5_rk * (x0(1:2) + y1(1:2))
        ! Rows in the pattern's order: (0: 0 2) (1: 1 3) (2: 0 2 4) (3: 1 3 4) (4: 0 1).
        v = [1.0_rk, -0.5_rk * h, 1.0_rk, -0.5_rk * h, &
             0.5_rk * y1(5), 1.0_rk, xm(1), 0.5_rk * y1(5), 1.0_rk, xm(2), &
             y1(1), y1(2)]
        status = 0
    end function pendulum_jacobian

    function pendulum_predictor(ctx, t_n, h, x_n, y) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        real(rk), pointer :: x0(:), y1(:)
        call c_f_pointer(x_n, x0, [4])
        call c_f_pointer(y, y1, [5])
        y1(1:4) = x0
        y1(5) = 0.0_rk
        status = 0
    end function pendulum_predictor

    function pendulum_update(ctx, t_n, h, x_n, y, x_np1) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y, x_np1
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        real(rk), pointer :: y1(:), x1(:)
        call c_f_pointer(y, y1, [5])
        call c_f_pointer(x_np1, x1, [4])
        x1 = y1(1:4)
        status = 0
    end function pendulum_update

    !> Records every accepted substep; for the pendulum also the constraint at its end.
    function record_poststep(ctx, t_n, h, x_n, x_np1, newton_its, fnorm) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, x_np1
        real(c_double), value :: t_n, h, fnorm
        integer(c_int), value :: newton_its
        integer(c_int) :: status
        type(problem_t), pointer :: p
        real(rk), pointer :: x1(:)
        call c_f_pointer(ctx, p)
        call c_f_pointer(x_np1, x1, [p%n_state])
        p%n_post = p%n_post + 1
        if (p%n_post <= max_records) then
            p%t_taken(p%n_post) = t_n
            p%h_taken(p%n_post) = h
        end if
        p%newton_its = p%newton_its + newton_its
        p%max_fnorm = max(p%max_fnorm, fnorm)
        p%sum_fnorm = p%sum_fnorm + fnorm
        if (p%kind == pendulum) p%max_constraint = max(p%max_constraint, &
            abs(x1(1)**2 + x1(2)**2 - 1.0_rk))
        status = 0
    end function record_poststep

    !> The invalid region of the cut-back tests, and the fatal status.
    integer(c_int) function check_state(p, t_n, h)
        type(problem_t), intent(in) :: p
        real(rk), intent(in) :: t_n, h
        check_state = 0
        if (h > p%h_limit .or. t_n + h > p%t_limit) check_state = 1
        if (p%fatal_status /= 0) check_state = int(p%fatal_status, c_int)
    end function check_state

    ! ---- Helpers ------------------------------------------------------------------------------

    !> Advance `x` over `n` steps of size h from t = 0; `ok` false (and a failed assertion) on
    !> the first error.
    subroutine run_steps(stepper, x, h, n, ok)
        type(rod_stepper_t), intent(inout) :: stepper
        real(rk), intent(inout) :: x(:)
        real(rk), intent(in) :: h
        integer, intent(in) :: n
        logical, intent(out) :: ok
        type(error_t), allocatable :: err
        integer :: i, substeps, cutbacks, its
        real(rk) :: fnorm
        ok = .true.
        do i = 1, n
            call stepper%advance(real(i - 1, rk) * h, h, x, substeps, cutbacks, its, fnorm, err)
            if (allocated(err)) then
                CHECK_TRUE(.false., 'advance: ' // err%message)
                ok = .false.
                return
            end if
        end do
    end subroutine run_steps

    pure real(rk) function oscillator_energy(x, omega)
        real(rk), intent(in) :: x(2), omega
        oscillator_energy = 0.5_rk * (x(2)**2 + omega**2 * x(1)**2)
    end function oscillator_energy

    !> Max-norm error of the oscillator (omega, q0 = 1, v0 = 0) at t = 1 after n steps.
    real(rk) function oscillator_error(kind, n) result(error)
        integer, intent(in) :: kind, n
        type(problem_t), target :: problem
        type(rod_stepper_t) :: stepper
        type(error_t), allocatable :: err
        real(rk) :: x(2)
        logical :: ok
        error = huge(1.0_rk)
        problem = new_problem(kind)
        problem%omega = 2.0_rk
        call create_stepper(stepper, problem, 6, err)
        if (allocated(err)) then
            CHECK_TRUE(.false., 'create: ' // err%message)
            return
        end if
        x = [1.0_rk, 0.0_rk]
        call run_steps(stepper, x, 1.0_rk / real(n, rk), n, ok)
        if (ok) error = maxval(abs(x - [cos(2.0_rk), -2.0_rk * sin(2.0_rk)]))
        call stepper%destroy()
    end function oscillator_error

    ! ---- Tests --------------------------------------------------------------------------------

    !> The midpoint rule keeps the quadratic energy of a linear oscillator exactly; what is left
    !> is the Newton residual (one iteration on a linear problem: round-off) and round-off.
    subroutine test_oscillator_energy()
        type(problem_t), target :: problem
        type(rod_stepper_t) :: stepper
        type(error_t), allocatable :: err
        real(rk) :: x(2), e0
        logical :: ok
        problem = new_problem(oscillator)
        problem%omega = 3.0_rk
        call create_stepper(stepper, problem, 6, err)
        if (allocated(err)) then
            CHECK_TRUE(.false., 'create: ' // err%message)
            return
        end if
        x = [0.7_rk, -1.3_rk]
        e0 = oscillator_energy(x, problem%omega)
        call run_steps(stepper, x, 0.01_rk, 1000, ok)
        CHECK_TRUE(ok, '1000 steps')
        CHECK_EQUAL(problem%n_post, 1000, 'one accepted substep per step')
        CHECK_EQUAL(problem%newton_its, 1000, 'linear problem: one Newton iteration per step')
        CHECK_TRUE(problem%max_fnorm < atol, 'every step converged to atol')
        CHECK_CLOSE(oscillator_energy(x, problem%omega), e0, 0.0_rk, 1.0e-13_rk, 'energy after 1000 steps')
        ! The state moved: a stepper that did nothing would also keep the energy.
        CHECK_TRUE(abs(x(1) - 0.7_rk) > 0.1_rk, 'the oscillator moved')
        call stepper%destroy()
        CHECK_TRUE(.not. stepper%is_created(), 'destroyed')
    end subroutine test_oscillator_energy

    !> Errors at t = 1 for h = 1/10, 1/20, 1/40: observed order 2 (both ratios).
    subroutine test_oscillator_order()
        real(rk) :: e(3), order
        integer :: i
        e = [oscillator_error(oscillator, 10), oscillator_error(oscillator, 20), &
             oscillator_error(oscillator, 40)]
        do i = 1, 2
            order = log(e(i) / e(i + 1)) / log(2.0_rk)
            CHECK_CLOSE(order, 2.0_rk, 0.05_rk, 0.0_rk, 'observed order')
        end do
        CHECK_TRUE(e(3) < 1.0e-2_rk, 'error small at h = 1/40')
    end subroutine test_oscillator_order

    !> Y = q_{n+1} only, with a predictor and an update: the same midpoint solution as with
    !> the full layout, and the callbacks were used once per step.
    subroutine test_reduced_unknowns()
        type(problem_t), target :: full, reduced
        type(rod_stepper_t) :: stepper_full, stepper_reduced
        type(error_t), allocatable :: err
        real(rk) :: x_full(2), x_reduced(2)
        logical :: ok
        full = new_problem(oscillator)
        reduced = new_problem(oscillator_reduced)
        call create_stepper(stepper_full, full, 6, err)
        if (allocated(err)) then
            CHECK_TRUE(.false., 'create full: ' // err%message)
            return
        end if
        call create_stepper(stepper_reduced, reduced, 6, err)
        if (allocated(err)) then
            CHECK_TRUE(.false., 'create reduced: ' // err%message)
            return
        end if
        x_full = [1.0_rk, 0.5_rk]
        x_reduced = x_full
        call run_steps(stepper_full, x_full, 0.05_rk, 100, ok)
        call run_steps(stepper_reduced, x_reduced, 0.05_rk, 100, ok)
        CHECK_CLOSE(x_reduced, x_full, 1.0e-12_rk, 0.0_rk, 'same solution as Y = X')
        CHECK_EQUAL(reduced%n_predictor, 100, 'predictor once per step')
        CHECK_EQUAL(reduced%n_update, 100, 'update once per step')
        CHECK_EQUAL(reduced%newton_its, 100, 'one Newton iteration per step (linear)')
        ! The explicit-Euler predictor is not the solution, so Newton had to work.
        CHECK_TRUE(reduced%max_fnorm < atol, 'converged')
        call stepper_full%destroy()
        call stepper_reduced%destroy()
    end subroutine test_reduced_unknowns

    !> A nonlinear saddle-point step: Newton needs several iterations, MUMPS pivots on the
    !> multiplier's zero diagonal, the constraint holds to 1e-14 at every step, energy to a
    !> multiple of the Newton residuals, and the LU analysis is done once for 200 steps.
    subroutine test_pendulum()
        type(problem_t), target :: problem
        type(rod_stepper_t) :: stepper
        type(error_t), allocatable :: err
        real(rk) :: x(4), e0, e1
        integer :: symbolic0, symbolic1, numeric0, numeric1
        logical :: ok
        problem = new_problem(pendulum)
        call petsc_event_count('MatLUFactorSym', symbolic0, err)
        if (allocated(err)) then
            CHECK_TRUE(.false., 'event count: ' // err%message)
            return
        end if
        call petsc_event_count('MatLUFactorNum', numeric0, err)
        call create_stepper(stepper, problem, 6, err)
        if (allocated(err)) then
            CHECK_TRUE(.false., 'create: ' // err%message)
            return
        end if
        x = [1.0_rk, 0.0_rk, 0.0_rk, 0.0_rk]
        e0 = 0.5_rk * sum(x(3:4)**2) + gravity * x(2)
        call run_steps(stepper, x, 0.01_rk, 200, ok)
        CHECK_TRUE(ok, '200 steps')
        CHECK_TRUE(problem%newton_its >= 2 * 200, 'several Newton iterations per step')
        CHECK_TRUE(problem%max_fnorm < atol, 'every step converged to atol 1e-12')
        CHECK_TRUE(problem%max_constraint <= 1.0e-14_rk, 'constraint |x|^2 = 1 to 1e-14 at every step')
        e1 = 0.5_rk * sum(x(3:4)**2) + gravity * x(2)
        CHECK_TRUE(abs(e1 - e0) <= 10.0_rk * problem%sum_fnorm + 1.0e-12_rk, 'energy to 10 x the sum of Newton residuals')
        CHECK_TRUE(x(2) < -0.5_rk, 'the pendulum fell')
        call petsc_event_count('MatLUFactorSym', symbolic1, err)
        call petsc_event_count('MatLUFactorNum', numeric1, err)
        CHECK_EQUAL(symbolic1 - symbolic0, 1, 'one symbolic factorization for the whole run')
        CHECK_EQUAL(numeric1 - numeric0, problem%newton_its, 'one numeric factorization per Newton iteration')
        call stepper%destroy()
    end subroutine test_pendulum

    !> The pendulum with the factored Jacobian kept while Newton contracts tenfold per iteration
    !> (&solver jacobian_reuse = 0.1): every step converged to atol, so the constraint holds to
    !> atol and energy to a multiple of the residuals; the state is Newton's method's to the
    !> tolerance; the Jacobians computed are the numeric factorizations done, and fewer than
    !> half the iterations.
    subroutine test_pendulum_reuse()
        type(problem_t), target :: problem, newton
        type(rod_stepper_t) :: stepper, reference
        type(error_t), allocatable :: err
        real(rk) :: x(4), x_newton(4), e0, e1
        integer :: numeric0, numeric1, jacobians, floor_steps
        logical :: ok
        problem = new_problem(pendulum)
        newton = new_problem(pendulum)
        call create_stepper(stepper, problem, 6, err, jacobian_reuse=0.1_rk)
        if (allocated(err)) then
            CHECK_TRUE(.false., 'create: ' // err%message)
            return
        end if
        call create_stepper(reference, newton, 6, err)
        call petsc_event_count('MatLUFactorNum', numeric0, err)
        x = [1.0_rk, 0.0_rk, 0.0_rk, 0.0_rk]
        e0 = 0.5_rk * sum(x(3:4)**2) + gravity * x(2)
        call run_steps(stepper, x, 0.01_rk, 200, ok)
        CHECK_TRUE(ok, '200 steps')
        call petsc_event_count('MatLUFactorNum', numeric1, err)
        CHECK_TRUE(problem%max_fnorm < atol, 'every step converged to atol 1e-12')
        CHECK_TRUE(problem%max_constraint <= atol, 'constraint |x|^2 = 1 to atol at every step')
        e1 = 0.5_rk * sum(x(3:4)**2) + gravity * x(2)
        CHECK_TRUE(abs(e1 - e0) <= 10.0_rk * problem%sum_fnorm + 1.0e-12_rk, 'energy to 10 x the sum of Newton residuals')
        call stepper%run_stats(jacobians, floor_steps)
        CHECK_EQUAL(jacobians, numeric1 - numeric0, 'one numeric factorization per Jacobian')
        CHECK_TRUE(2 * jacobians < problem%newton_its, 'fewer Jacobians than half the iterations')
        CHECK_EQUAL(floor_steps, 0, 'no step at the rounding floor (atol is above it)')
        x_newton = [1.0_rk, 0.0_rk, 0.0_rk, 0.0_rk]
        call run_steps(reference, x_newton, 0.01_rk, 200, ok)
        call reference%run_stats(jacobians, floor_steps)
        CHECK_EQUAL(jacobians, newton%newton_its, "Newton's method: a Jacobian per iteration")
        CHECK_CLOSE(x, x_newton, 1.0e-9_rk, 0.0_rk, "the state of Newton's method to 200 x the tolerance")
        call stepper%destroy()
        call reference%destroy()
    end subroutine test_pendulum_reuse

    !> The cut-back case with a kept Jacobian: a trial step into the invalid region is no
    !> failure (the Jacobian is made anew at the iterate), so the substeps and halvings are
    !> those of Newton's method.
    subroutine test_cutback_reuse()
        type(problem_t), target :: limited
        type(rod_stepper_t) :: stepper
        type(error_t), allocatable :: err
        real(rk) :: x(2), fnorm
        integer :: substeps, cutbacks, its
        limited = new_problem(oscillator)
        call create_stepper(stepper, limited, 6, err, jacobian_reuse=0.1_rk)
        if (allocated(err)) then
            CHECK_TRUE(.false., 'create: ' // err%message)
            return
        end if
        x = [1.0_rk, 0.0_rk]
        call stepper%advance(0.0_rk, 0.01_rk, x, substeps, cutbacks, its, fnorm, err)
        CHECK_TRUE(.not. allocated(err), 'a first step keeps its Jacobian')
        limited%h_limit = 0.03_rk
        call stepper%advance(0.01_rk, 0.1_rk, x, substeps, cutbacks, its, fnorm, err)
        CHECK_TRUE(.not. allocated(err), 'advance with cut-backs succeeds')
        if (allocated(err)) return
        CHECK_EQUAL(substeps, 4, 'substeps')
        CHECK_EQUAL(cutbacks, 5, "halvings as with Newton's method")
        call stepper%destroy()
    end subroutine test_cutback_reuse

    !> dt = 0.1 with an invalid state for h > 0.03: substeps 0.025 (2 halvings), 0.01875 (2),
    !> 0.028125 (1), 0.028125 (0); the result equals taking those steps directly.
    subroutine test_cutback_succeeds()
        type(problem_t), target :: limited, direct
        type(rod_stepper_t) :: stepper, reference
        type(error_t), allocatable :: err
        real(rk) :: x(2), x_direct(2), fnorm, t, expected_h(4)
        integer :: substeps, cutbacks, its, i, s, c, k
        limited = new_problem(oscillator)
        limited%h_limit = 0.03_rk
        direct = new_problem(oscillator)
        call create_stepper(stepper, limited, 6, err)
        if (allocated(err)) then
            CHECK_TRUE(.false., 'create: ' // err%message)
            return
        end if
        x = [1.0_rk, 0.0_rk]
        call stepper%advance(0.0_rk, 0.1_rk, x, substeps, cutbacks, its, fnorm, err)
        CHECK_TRUE(.not. allocated(err), 'advance with cut-backs succeeds')
        if (allocated(err)) return
        CHECK_EQUAL(substeps, 4, 'substeps')
        CHECK_EQUAL(cutbacks, 5, 'halvings')
        CHECK_EQUAL(its, 4, 'Newton iterations of the accepted substeps')
        CHECK_EQUAL(limited%n_post, 4, 'poststep once per accepted substep')
        expected_h = [0.025_rk, 0.01875_rk, 0.028125_rk, 0.028125_rk]
        CHECK_CLOSE(limited%h_taken(1:4), expected_h, 1.0e-16_rk, 0.0_rk, 'substep sizes')
        CHECK_CLOSE(sum(limited%h_taken(1:4)), 0.1_rk, 1.0e-16_rk, 0.0_rk, 'exactly dt in total')
        CHECK_CLOSE(limited%t_taken(4), 0.1_rk - 0.028125_rk, 1.0e-16_rk, 0.0_rk, 'time of the last substep')

        call create_stepper(reference, direct, 0, err)
        if (allocated(err)) then
            CHECK_TRUE(.false., 'create reference: ' // err%message)
            return
        end if
        x_direct = [1.0_rk, 0.0_rk]
        t = 0.0_rk
        k = 0
        do i = 1, 4
            call reference%advance(t, limited%h_taken(i), x_direct, s, c, its, fnorm, err)
            if (allocated(err)) exit
            k = k + c
            t = t + limited%h_taken(i)
        end do
        CHECK_TRUE(.not. allocated(err), 'the small steps directly')
        CHECK_EQUAL(k, 0, 'no cut-back when stepping directly')
        CHECK_CLOSE(x, x_direct, 1.0e-15_rk, 0.0_rk, 'same answer as the small steps')
        ! The cut state still advanced: the next call takes a whole dt again (step grows back).
        limited%h_limit = huge(1.0_rk)
        call stepper%advance(0.1_rk, 0.1_rk, x, substeps, cutbacks, its, fnorm, err)
        CHECK_TRUE(.not. allocated(err), 'next advance')
        CHECK_EQUAL(substeps, 1, 'next advance in one step')
        CHECK_EQUAL(cutbacks, 0, 'next advance without cut-back')
        call stepper%destroy()
        call reference%destroy()
    end subroutine test_cutback_succeeds

    !> max_cutbacks = 2 and invalid states beyond t = 0.05: substeps 0.025 and 0.01875 are
    !> accepted, the third from t = 0.04375 fails with 0.05625, 0.028125, 0.0140625. x is the
    !> state at t = 0.04375, equal to taking the two accepted steps directly.
    subroutine test_cutback_fails()
        type(problem_t), target :: limited, direct
        type(rod_stepper_t) :: stepper, reference
        type(error_t), allocatable :: err
        real(rk) :: x(2), x_direct(2), fnorm
        integer :: substeps, cutbacks, its, s, c
        logical :: diverged
        limited = new_problem(oscillator)
        limited%h_limit = 0.03_rk
        limited%t_limit = 0.05_rk
        direct = new_problem(oscillator)
        call create_stepper(stepper, limited, 2, err)
        if (allocated(err)) then
            CHECK_TRUE(.false., 'create: ' // err%message)
            return
        end if
        x = [1.0_rk, 0.0_rk]
        call stepper%advance(0.0_rk, 0.1_rk, x, substeps, cutbacks, its, fnorm, err, diverged)
        CHECK_TRUE(allocated(err), 'advance fails')
        if (.not. allocated(err)) return
        CHECK_TRUE(diverged, 'reported as a Newton failure, not a PETSc error')
        CHECK_CONTAINS(err%message, 'Newton did not converge at t = 0.04375 after 2 halvings of the step', 'message: where')
        CHECK_CONTAINS(err%message, 'smallest step 0.0140625', 'message: smallest step')
        CHECK_CONTAINS(err%message, 'last SNES reason DIVERGED_FUNCTION_DOMAIN', 'message: why')
        CHECK_EQUAL(substeps, 2, 'accepted substeps before the failure')
        CHECK_EQUAL(cutbacks, 6, 'halvings: 4 of the accepted substeps, 2 of the failing one')

        call create_stepper(reference, direct, 0, err)
        if (allocated(err)) then
            CHECK_TRUE(.false., 'create reference: ' // err%message)
            return
        end if
        x_direct = [1.0_rk, 0.0_rk]
        call reference%advance(0.0_rk, 0.025_rk, x_direct, s, c, its, fnorm, err)
        call reference%advance(0.025_rk, 0.01875_rk, x_direct, s, c, its, fnorm, err)
        CHECK_TRUE(.not. allocated(err), 'the accepted steps directly')
        CHECK_CLOSE(x, x_direct, 1.0e-15_rk, 0.0_rk, 'x is the last good state')
        CHECK_TRUE(abs(x(2)) > 1.0e-3_rk, 'the last good state is not the initial one')
        call stepper%destroy()
        call reference%destroy()
    end subroutine test_cutback_fails

    !> scene value < petsc_options < command line (-snes_max_funcs 3000, given to
    !> PetscInitialize by the test program). Checked on the SNES itself and in the option text.
    subroutine test_options_precedence()
        type(problem_t), target :: problem
        type(rod_stepper_t) :: stepper
        type(error_t), allocatable :: err
        real(rk) :: a, r, s
        integer :: max_it, max_funcs, max_cutbacks
        character(len=:), allocatable :: types, text
        problem = new_problem(oscillator)

        call petsc_apply_options('-snes_max_it 3 -snes_max_funcs 1000', &
            '-snes_max_it 5 -snes_max_funcs 2000 -ts_rodmid_max_cutbacks 9', err)
        CHECK_TRUE(.not. allocated(err), 'apply options')
        ! The stepper's own scene values: max_newton = 3, max_cutbacks = 6, atol 1e-12.
        call create_stepper(stepper, problem, 6, err, max_newton=3)
        if (allocated(err)) then
            CHECK_TRUE(.false., 'create: ' // err%message)
            return
        end if
        call stepper%solver_settings(a, r, s, max_it, max_funcs, max_cutbacks, types, err)
        CHECK_TRUE(.not. allocated(err), 'settings')
        CHECK_EQUAL(max_it, 5, 'petsc_options beat the scene value of -snes_max_it')
        CHECK_EQUAL(max_funcs, 3000, 'the command line beats petsc_options and the scene')
        CHECK_EQUAL(max_cutbacks, 9, 'petsc_options beat the scene value of max_cutbacks')
        CHECK_CLOSE(a, atol, 0.0_rk, 0.0_rk, 'scene value of atol where nobody overrides it')
        CHECK_CLOSE(r, 0.0_rk, 0.0_rk, 0.0_rk, 'rtol 0')
        CHECK_CLOSE(s, 0.0_rk, 0.0_rk, 0.0_rk, 'stol 0')
        ! The LU package of a single rod: the chain LU (include/rs_rodchain.h).
        CHECK_EQUAL(types, 'snes newtonls linesearch bt ksp preonly pc lu solver rodchain', 'solver chain')
        text = petsc_options_text()
        CHECK_CONTAINS(text, '-snes_max_it 5', 'option text: petsc_options value')
        CHECK_CONTAINS(text, '-snes_max_funcs 3000', 'option text: command-line value')
        CHECK_CONTAINS(text, '-mat_mumps_icntl_14 50', 'option text: scene default')
        call stepper%destroy()

        ! An empty petsc_options layer: its names go, the command line stays.
        call petsc_apply_options(user_options='', err=err)
        CHECK_TRUE(.not. allocated(err), 'clear petsc_options')
        call create_stepper(stepper, problem, 4, err, max_newton=7)
        if (allocated(err)) then
            CHECK_TRUE(.false., 'create again: ' // err%message)
            return
        end if
        call stepper%solver_settings(a, r, s, max_it, max_funcs, max_cutbacks, types, err)
        CHECK_EQUAL(max_it, 7, 'scene value once petsc_options no longer set it')
        CHECK_EQUAL(max_cutbacks, 4, 'scene max_cutbacks once petsc_options no longer set it')
        CHECK_EQUAL(max_funcs, 3000, 'the command line still wins')
        call stepper%destroy()

        ! PETSc parses the strings: an options file that does not exist is an error.
        call petsc_apply_options(user_options='-options_file /nonexistent/rodsolve.opts', err=err)
        CHECK_TRUE(allocated(err), 'a missing options file is an error')
        if (allocated(err)) CHECK_CONTAINS(err%message, 'the PETSc options could not be applied', 'message')
        if (allocated(err)) CHECK_CONTAINS(err%message, '/nonexistent/rodsolve.opts', 'message names the string')
        call petsc_apply_options(user_options='', err=err)
    end subroutine test_options_precedence

    !> TSView prints the rodmid line with the cut-back limit.
    subroutine test_view()
        type(problem_t), target :: problem
        type(rod_stepper_t) :: stepper
        type(error_t), allocatable :: err
        character(len=*), parameter :: path = 'test_rod_stepper_view.txt'
        character(len=256) :: line
        character(len=:), allocatable :: text
        real(rk) :: x(2), fnorm
        integer :: unit, ios, substeps, cutbacks, its
        problem = new_problem(oscillator)
        call create_stepper(stepper, problem, 5, err)
        if (allocated(err)) then
            CHECK_TRUE(.false., 'create: ' // err%message)
            return
        end if
        ! After one step the PC is set up and its view names the factorization package.
        x = [1.0_rk, 0.0_rk]
        call stepper%advance(0.0_rk, 0.1_rk, x, substeps, cutbacks, its, fnorm, err)
        CHECK_TRUE(.not. allocated(err), 'advance')
        call stepper%view(path, err)
        CHECK_TRUE(.not. allocated(err), 'view')
        text = ''
        open(newunit=unit, file=path, status='old', action='read', iostat=ios)
        CHECK_EQUAL(ios, 0, 'view file exists')
        if (ios /= 0) return
        do
            read(unit, '(a)', iostat=ios) line
            if (ios /= 0) exit
            text = text // trim(line) // new_line('a')
        end do
        close(unit, status='delete')
        CHECK_CONTAINS(text, 'type: rodmid', 'TS type')
        CHECK_CONTAINS(text, 'rodmid: implicit midpoint on a user step problem, max cutbacks 5', 'rodmid line')
        CHECK_CONTAINS(text, 'package used to perform factorization: rodchain', 'chain LU in the PC view')
        call stepper%destroy()
    end subroutine test_view

    !> Each field of the traits struct reaches the solver: atol, rtol, the iteration and cut-back
    !> limits and the reuse ratio with values no other field has (a field read at another
    !> offset would show another value), and the four flags in three combinations such that any
    !> two flags differ in one of them (PETSc's own LU with the natural or the
    !> nested-dissection ordering or the chain LU, full or backtracking Newton, KSPONLY or
    !> newtonls).
    subroutine test_traits_reach_the_solver()
        type(problem_t), target :: problem
        type(rod_stepper_t) :: stepper
        type(error_t), allocatable :: err
        type(stepper_traits_t) :: traits
        real(rk) :: a, r, s
        integer :: max_it, max_funcs, max_cutbacks
        character(len=:), allocatable :: types
        problem = new_problem(oscillator)
        traits = stepper_traits_t(newton_atol=3.0e-11_rk, newton_rtol=7.0e-9_rk, &
            jacobian_reuse=0.25_rk, max_newton=17, max_cutbacks=4)
        call create_with(traits, native_lu=.true., banded_unknowns=.true., full_newton=.false., &
            linear_step=.false., types='snes newtonls linesearch bt ksp preonly pc lu solver petsc', &
            view_has=['matrix ordering: natural                   ', &
                      'max cutbacks 4, Jacobian reuse ratio 0.25  '])
        call stepper%solver_settings(a, r, s, max_it, max_funcs, max_cutbacks, types, err)
        CHECK_TRUE(.not. allocated(err), 'settings')
        CHECK_CLOSE(a, 3.0e-11_rk, 0.0_rk, 0.0_rk, 'newton_atol')
        CHECK_CLOSE(r, 7.0e-9_rk, 0.0_rk, 0.0_rk, 'newton_rtol')
        CHECK_EQUAL(max_it, 17, 'max_newton')
        CHECK_EQUAL(max_cutbacks, 4, 'max_cutbacks')
        call create_with(traits, native_lu=.true., banded_unknowns=.false., full_newton=.true., &
            linear_step=.true., types='snes ksponly linesearch basic ksp preonly pc lu solver petsc', &
            view_has=['matrix ordering: nd                        ', &
                      'max cutbacks 4                             '])
        call create_with(traits, native_lu=.false., banded_unknowns=.false., full_newton=.true., &
            linear_step=.false., &
            types='snes newtonls linesearch basic ksp preonly pc lu solver rodchain', &
            view_has=['package used to perform factorization: rodchain', &
                      'Jacobian reuse ratio 0.25                      '])
        call stepper%destroy()

    contains

        !> Create the oscillator's stepper with `traits` and these flags, take one step and
        !> check the solver types and lines of the view.
        subroutine create_with(traits, native_lu, banded_unknowns, full_newton, linear_step, &
                types, view_has)
            type(stepper_traits_t), intent(inout) :: traits
            logical, intent(in) :: native_lu, banded_unknowns, full_newton, linear_step
            character(len=*), intent(in) :: types, view_has(:)
            character(len=:), allocatable :: actual, text
            real(rk) :: x(2), fnorm
            integer :: i, substeps, cutbacks, its
            traits%native_lu = native_lu
            traits%banded_unknowns = banded_unknowns
            traits%full_newton = full_newton
            traits%linear_step = linear_step
            call stepper%create(2, 2, [0, 2, 4], [0, 1, 0, 1], c_funloc(oscillator_residual), &
                c_funloc(oscillator_jacobian), c_null_funptr, c_null_funptr, c_null_funptr, &
                c_loc(problem), traits, err)
            if (allocated(err)) then
                CHECK_TRUE(.false., 'create: ' // err%message)
                return
            end if
            call stepper%solver_settings(a, r, s, max_it, max_funcs, max_cutbacks, actual, err)
            CHECK_EQUAL(actual, types, 'solver types of the flags')
            x = [1.0_rk, 0.0_rk]
            call stepper%advance(0.0_rk, 0.1_rk, x, substeps, cutbacks, its, fnorm, err)
            CHECK_TRUE(.not. allocated(err), 'advance')
            text = view_text(stepper)
            do i = 1, size(view_has)
                CHECK_CONTAINS(text, trim(view_has(i)), 'the view')
            end do
        end subroutine create_with
    end subroutine test_traits_reach_the_solver

    !> The stepper's TSView as text.
    function view_text(stepper) result(text)
        type(rod_stepper_t), intent(in) :: stepper
        character(len=:), allocatable :: text
        character(len=*), parameter :: path = 'test_rod_stepper_traits_view.txt'
        character(len=256) :: line
        type(error_t), allocatable :: err
        integer :: unit, ios
        text = ''
        call stepper%view(path, err)
        CHECK_TRUE(.not. allocated(err), 'view')
        open(newunit=unit, file=path, status='old', action='read', iostat=ios)
        CHECK_EQUAL(ios, 0, 'view file exists')
        if (ios /= 0) return
        do
            read(unit, '(a)', iostat=ios) line
            if (ios /= 0) exit
            text = text // trim(line) // new_line('a')
        end do
        close(unit, status='delete')
    end function view_text

    !> Unsorted columns and wrong array sizes are reported with what is wrong.
    subroutine test_bad_pattern()
        type(problem_t), target :: problem
        type(rod_stepper_t) :: stepper
        type(error_t), allocatable :: err
        problem = new_problem(oscillator)
        call stepper%create(2, 2, [0, 2, 4], [1, 0, 0, 1], c_funloc(oscillator_residual), &
            c_funloc(oscillator_jacobian), c_null_funptr, c_null_funptr, c_null_funptr, &
            c_loc(problem), stepper_traits_t(newton_atol=atol, max_newton=25, max_cutbacks=6), err)
        CHECK_TRUE(allocated(err), 'unsorted columns rejected')
        if (allocated(err)) CHECK_CONTAINS(err%message, 'columns of row 0 (0-based) are not strictly increasing', 'message')
        CHECK_TRUE(.not. stepper%is_created(), 'nothing created')
        call stepper%create(2, 2, [0, 2, 4], [0, 1, 0], c_funloc(oscillator_residual), &
            c_funloc(oscillator_jacobian), c_null_funptr, c_null_funptr, c_null_funptr, &
            c_loc(problem), stepper_traits_t(newton_atol=atol, max_newton=25, max_cutbacks=6), err)
        CHECK_TRUE(allocated(err), 'short cols rejected')
        if (allocated(err)) CHECK_CONTAINS(err%message, 'cols has 3 entries; the pattern (row_ptr) has 4', 'message')
        call stepper%create(2, 1, [0, 1], [0], c_funloc(reduced_residual), &
            c_funloc(reduced_jacobian), c_null_funptr, c_null_funptr, c_null_funptr, &
            c_loc(problem), stepper_traits_t(newton_atol=atol, max_newton=25, max_cutbacks=6), err)
        CHECK_TRUE(allocated(err), 'Y smaller than X without predictor and update rejected')
        if (allocated(err)) CHECK_CONTAINS(err%message, 'a predictor and an update callback are required', 'message')
    end subroutine test_bad_pattern

    !> A residual status other than 0 and 1 stops the advance with an error naming it.
    subroutine test_fatal_callback()
        type(problem_t), target :: problem
        type(rod_stepper_t) :: stepper
        type(error_t), allocatable :: err
        real(rk) :: x(2), fnorm
        integer :: substeps, cutbacks, its
        logical :: diverged
        problem = new_problem(oscillator)
        call create_stepper(stepper, problem, 6, err)
        if (allocated(err)) then
            CHECK_TRUE(.false., 'create: ' // err%message)
            return
        end if
        problem%fatal_status = 7
        x = [1.0_rk, 0.0_rk]
        call stepper%advance(0.0_rk, 0.1_rk, x, substeps, cutbacks, its, fnorm, err, diverged)
        CHECK_TRUE(allocated(err), 'fatal status is an error')
        if (allocated(err)) CHECK_CONTAINS(err%message, 'the residual callback failed with status 7 at t = 0', 'message')
        CHECK_TRUE(.not. diverged, 'not a Newton failure')
        call stepper%destroy()
    end subroutine test_fatal_callback

    !> With -pc_factor_mat_solver_type petsc (in petsc_options) the pendulum's zero diagonal
    !> stops PETSc's own LU: the reason rodsolve defaults to MUMPS (DESIGN.md §3).
    subroutine test_native_lu_fails()
        type(problem_t), target :: problem
        type(rod_stepper_t) :: stepper
        type(error_t), allocatable :: err
        real(rk), parameter :: x0(4) = [1.0_rk, 0.0_rk, 0.0_rk, 0.0_rk]
        real(rk) :: x(4), fnorm
        integer :: substeps, cutbacks, its
        problem = new_problem(pendulum)
        call petsc_apply_options(user_options='-pc_factor_mat_solver_type petsc', err=err)
        call create_stepper(stepper, problem, 6, err)
        if (allocated(err)) then
            CHECK_TRUE(.false., 'create: ' // err%message)
            return
        end if
        x = x0
        call stepper%advance(0.0_rk, 0.01_rk, x, substeps, cutbacks, its, fnorm, err)
        CHECK_TRUE(allocated(err), 'native LU fails')
        if (allocated(err)) CHECK_CONTAINS(err%message, 'missing diagonal', 'PETSc''s message reaches Fortran')
        CHECK_CLOSE(x, x0, 0.0_rk, 0.0_rk, 'x untouched')
        call stepper%destroy()
        call petsc_apply_options(user_options='', err=err)
    end subroutine test_native_lu_fails

end module rs_test_solver_rod_stepper

!> Test program: starts PETSc with its own arguments plus `-snes_max_funcs 3000` (the
!> command-line layer of the precedence test), turns event logging on (to count
!> factorizations), runs the tests and exits non-zero if any failed.
program test_rod_stepper
    use rs_core_error, only: error_t
    use rs_solver_petsc_env, only: petsc_initialize, petsc_finalize
    use rs_solver_rod_stepper, only: petsc_log_begin
    use rs_test_solver_rod_stepper, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    type(error_t), allocatable :: err
    character(len=256), allocatable :: args(:)
    integer :: i, n
    n = command_argument_count()
    allocate(args(n + 2))
    do i = 1, n
        call get_command_argument(i, args(i))
    end do
    args(n + 1) = '-snes_max_funcs'
    args(n + 2) = '3000'
    call petsc_initialize('test_rod_stepper', args, err)
    if (allocated(err)) error stop 'PETSc did not start'
    call petsc_log_begin(err)
    if (allocated(err)) error stop 'PETSc logging did not start'
    call run_all_tests()
    call petsc_finalize()
    call finish_tests()
end program test_rod_stepper
