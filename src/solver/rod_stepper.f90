#include "rs_macros.h"
!> The rod stepper from Fortran: `bind(C)` interfaces to src/solver/rod_stepper.c (one rodmid
!> TS on PETSC_COMM_SELF per rod, DESIGN.md §3 and §5) and to the run's PETSc options
!> (src/solver/petsc_init.c), with thin wrappers that return `type(error_t)`.
!>
!> Callbacks are `bind(C)` procedures with the abstract interfaces below, passed as
!> `c_funloc(procedure)`; their context is any `target` passed as `c_loc(object)`, typically a
!> non-polymorphic type holding a pointer to the formulation (DESIGN.md §3, "Callbacks from
!> Fortran"). Arrays arrive as C pointers: `call c_f_pointer(y, y_, [n_unknown])`. Return 0,
!> or 1 from the residual or Jacobian for an invalid state (the step is halved), anything else
!> for a fatal error.
!>
!> Options precedence (DESIGN.md §3): scene values < the input's `petsc_options` < the
!> command line. The command line is captured when PETSc starts; `petsc_apply_options` sets the
!> `petsc_options` layer (once, at start-up) and scene values; `rod_stepper_t%create` inserts
!> its own scene values (newton_atol, newton_rtol, max_newton, max_cutbacks of its
!> stepper_traits_t, the LU package) in the scene layer, so a name set by a higher layer keeps
!> the higher layer's value.
module rs_solver_rod_stepper
    use, intrinsic :: iso_c_binding, only: c_int, c_double, c_bool, c_char, c_ptr, c_funptr, &
        c_null_ptr, c_null_char, c_loc, c_associated
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error, set_petsc_error
    use rs_core_strings, only: str, to_c_string, from_c_string
    implicit none
    private

    public :: rod_stepper_t, stepper_traits_t
    public :: petsc_apply_options, petsc_options_text, petsc_log_begin, petsc_event_count, &
        petsc_unused_options
    public :: residual_callback, jacobian_callback, predictor_callback, update_callback, &
        poststep_callback, admissible_callback

    !> Callback status: the state is fine.
    integer(c_int), parameter, public :: callback_ok = 0
    !> Callback status of a residual or Jacobian: invalid state, cut the step.
    integer(c_int), parameter, public :: callback_invalid_state = 1

    !> What a stepper is built with besides its pattern and callbacks: the scene's Newton
    !> settings (&solver) and the formulation's solver traits (rs_formulations_formulation's
    !> formulation_traits_t). It is `struct rs_stepper_traits` of include/rs_rod_stepper.h,
    !> which documents each field: the components and their order must match it.
    type, bind(C) :: stepper_traits_t
        !> Newton's absolute and relative residual tests (scene values, DESIGN.md §3).
        real(c_double) :: newton_atol = 0.0_c_double
        real(c_double) :: newton_rtol = 0.0_c_double
        !> Keep the factored Jacobian while each Newton iteration cuts the residual norm at
        !> least by this ratio (&solver jacobian_reuse); 0: Newton's method.
        real(c_double) :: jacobian_reuse = 0.0_c_double
        integer(c_int) :: max_newton = 0
        !> Halvings of a failing substep before the advance gives up.
        integer(c_int) :: max_cutbacks = 0
        !> PETSc's own LU instead of the chain LU: the Jacobian needs no pivoting.
        logical(c_bool) :: native_lu = .false.
        !> With native_lu: the unknowns are numbered for a narrow band, the LU keeps their order.
        logical(c_bool) :: banded_unknowns = .false.
        !> Full Newton steps instead of backtracking.
        logical(c_bool) :: full_newton = .false.
        !> The step problem is affine in y: one linear solve per step, no Newton loop.
        logical(c_bool) :: linear_step = .false.
        !> Order of the time integrator (&time order): 2, one midpoint step per step; 4, the
        !> five-stage composition of midpoint steps (include/rs_rod_stepper.h).
        integer(c_int) :: order = 2
        !> Error-controlled steps (&time adaptive): the steps inside an advance are PETSc
        !> TSAdapt's, from the local error weighed by atol and rtol, in [dt_min, dt_max],
        !> starting from dt_initial (include/rs_rod_stepper.h).
        logical(c_bool) :: adaptive = .false.
        real(c_double) :: atol = 0.0_c_double
        real(c_double) :: rtol = 0.0_c_double
        real(c_double) :: dt_min = 0.0_c_double
        real(c_double) :: dt_max = 0.0_c_double
        real(c_double) :: dt_initial = 0.0_c_double
    end type stepper_traits_t

    !> One rod's stepper: a handle to the C object and the state length it expects.
    type :: rod_stepper_t
        private
        type(c_ptr) :: handle = c_null_ptr
        integer :: n_state = 0
    contains
        !> Build the TS, its SNES/KSP/PC and the preallocated Jacobian (destroys an old one).
        procedure :: create => rod_stepper_create
        !> A shared system: the entries this rank's evaluations read (rs_stepper_set_needed).
        procedure :: set_needed => rod_stepper_set_needed
        !> Advance the state by exactly dt (with substeps and cut-backs).
        procedure :: advance => rod_stepper_advance
        !> The solver actually configured after all options.
        procedure :: solver_settings => rod_stepper_solver_settings
        !> Bordered solves of a Newton method run by the caller (arc-length continuation): the
        !> Jacobian values factored by the stepper's own linear solver, then solved for any
        !> number of right-hand sides (include/rs_rod_stepper.h).
        procedure :: factor => rod_stepper_factor
        procedure :: solve => rod_stepper_solve
        !> TSView (with SNES, KSP, PC) into a file, or standard output for an empty path.
        procedure :: view => rod_stepper_view
        !> Since create: Jacobians computed (each one a numeric factorization), and steps
        !> accepted at the rounding floor above newton_atol (include/rs_rodmid.h).
        procedure :: run_stats => rod_stepper_run_stats
        !> The feasible-step filter of the Newton solves (include/rs_rod_stepper.h).
        procedure :: set_admissible => rod_stepper_set_admissible
        !> Adaptive steppers: the load kinks their steps hit (rs_stepper_set_breakpoints).
        procedure :: set_breakpoints => rod_stepper_set_breakpoints
        !> Adaptive steppers: the state entries whose local error is controlled.
        procedure :: set_error_entries => rod_stepper_set_error_entries
        !> Adaptive steppers: steps rejected by the error control, smallest and largest step.
        procedure :: adaptive_stats => rod_stepper_adaptive_stats
        !> True between create and destroy.
        procedure :: is_created => rod_stepper_is_created
        !> Free the PETSc objects; safe to call twice.
        procedure :: destroy => rod_stepper_destroy
    end type rod_stepper_t

    abstract interface
        !> F(y; x_n, t_n, h), n_unknown entries: 0 ok, 1 invalid state, other fatal.
        function residual_callback(ctx, t_n, h, x_n, y, f) result(status) bind(C)
            import :: c_ptr, c_double, c_int
            type(c_ptr), value :: ctx, x_n, y, f
            real(c_double), value :: t_n, h
            integer(c_int) :: status
        end function residual_callback
        !> dF/dy into `values` in the order of the CSR pattern: 0 ok, 1 invalid state, other fatal.
        function jacobian_callback(ctx, t_n, h, x_n, y, values) result(status) bind(C)
            import :: c_ptr, c_double, c_int
            type(c_ptr), value :: ctx, x_n, y, values
            real(c_double), value :: t_n, h
            integer(c_int) :: status
        end function jacobian_callback
        !> 0 when y is an admissible iterate of the step from x_n, 1 when not.
        function admissible_callback(ctx, t_n, h, x_n, y) result(status) bind(C)
            import :: c_ptr, c_double, c_int
            type(c_ptr), value :: ctx, x_n, y
            real(c_double), value :: t_n, h
            integer(c_int) :: status
        end function admissible_callback
        !> The first Newton iterate y: 0 ok, other fatal.
        function predictor_callback(ctx, t_n, h, x_n, y) result(status) bind(C)
            import :: c_ptr, c_double, c_int
            type(c_ptr), value :: ctx, x_n, y
            real(c_double), value :: t_n, h
            integer(c_int) :: status
        end function predictor_callback
        !> x_{n+1} from the converged y: 0 ok, other fatal.
        function update_callback(ctx, t_n, h, x_n, y, x_np1) result(status) bind(C)
            import :: c_ptr, c_double, c_int
            type(c_ptr), value :: ctx, x_n, y, x_np1
            real(c_double), value :: t_n, h
            integer(c_int) :: status
        end function update_callback
        !> After each accepted (sub)step [t_n, t_n + h]: 0 ok, other fatal.
        function poststep_callback(ctx, t_n, h, x_n, x_np1, newton_its, fnorm) result(status) &
                bind(C)
            import :: c_ptr, c_double, c_int
            type(c_ptr), value :: ctx, x_n, x_np1
            real(c_double), value :: t_n, h, fnorm
            integer(c_int), value :: newton_its
            integer(c_int) :: status
        end function poststep_callback
    end interface

    interface
        integer(c_int) function rs_stepper_create(handle, n_state, n_unknown, row_ptr, cols, &
                residual, jacobian, predictor, update, poststep, ctx, traits, owned, n_blocks, &
                block_lengths, errmsg, errlen) bind(C)
            import :: c_int, c_char, c_ptr, c_funptr, stepper_traits_t
            type(c_ptr), intent(out) :: handle
            integer(c_int), value :: n_state, n_unknown
            integer(c_int), intent(in) :: row_ptr(*), cols(*)
            type(c_funptr), value :: residual, jacobian, predictor, update, poststep
            type(c_ptr), value :: ctx
            type(stepper_traits_t), intent(in) :: traits
            type(c_ptr), value :: owned
            integer(c_int), value :: n_blocks
            type(c_ptr), value :: block_lengths
            character(kind=c_char), intent(out) :: errmsg(*)
            integer(c_int), value :: errlen
        end function rs_stepper_create
        integer(c_int) function rs_stepper_set_needed(handle, n_state, state_entries, &
                n_unknown, unknown_entries, errmsg, errlen) bind(C)
            import :: c_int, c_char, c_ptr
            type(c_ptr), value :: handle
            integer(c_int), value :: n_state, n_unknown
            integer(c_int), intent(in) :: state_entries(*), unknown_entries(*)
            character(kind=c_char), intent(out) :: errmsg(*)
            integer(c_int), value :: errlen
        end function rs_stepper_set_needed
        integer(c_int) function rs_stepper_advance(handle, t_n, dt, x, substeps, cutbacks, &
                newton_its, fnorm, errmsg, errlen) bind(C)
            import :: c_int, c_double, c_char, c_ptr
            type(c_ptr), value :: handle
            real(c_double), value :: t_n, dt
            real(c_double), intent(inout) :: x(*)
            integer(c_int), intent(out) :: substeps, cutbacks, newton_its
            real(c_double), intent(out) :: fnorm
            character(kind=c_char), intent(out) :: errmsg(*)
            integer(c_int), value :: errlen
        end function rs_stepper_advance
        integer(c_int) function rs_stepper_factor(handle, values, singular, errmsg, errlen) &
                bind(C)
            import :: c_int, c_double, c_char, c_ptr
            type(c_ptr), value :: handle
            real(c_double), intent(in) :: values(*)
            integer(c_int), intent(out) :: singular
            character(kind=c_char), intent(out) :: errmsg(*)
            integer(c_int), value :: errlen
        end function rs_stepper_factor
        integer(c_int) function rs_stepper_solve(handle, rhs, sol, failed, errmsg, errlen) &
                bind(C)
            import :: c_int, c_double, c_char, c_ptr
            type(c_ptr), value :: handle
            real(c_double), intent(in) :: rhs(*)
            real(c_double), intent(out) :: sol(*)
            integer(c_int), intent(out) :: failed
            character(kind=c_char), intent(out) :: errmsg(*)
            integer(c_int), value :: errlen
        end function rs_stepper_solve
        integer(c_int) function rs_stepper_solver_settings(handle, atol, rtol, stol, max_it, &
                max_funcs, max_cutbacks, types, length) bind(C)
            import :: c_int, c_double, c_char, c_ptr
            type(c_ptr), value :: handle
            real(c_double), intent(out) :: atol, rtol, stol
            integer(c_int), intent(out) :: max_it, max_funcs, max_cutbacks
            character(kind=c_char), intent(out) :: types(*)
            integer(c_int), value :: length
        end function rs_stepper_solver_settings
        integer(c_int) function rs_stepper_run_stats(handle, jacobians, floor_steps) bind(C)
            import :: c_int, c_ptr
            type(c_ptr), value :: handle
            integer(c_int), intent(out) :: jacobians, floor_steps
        end function rs_stepper_run_stats
        integer(c_int) function rs_stepper_set_admissible(handle, admissible) bind(C)
            import :: c_int, c_ptr, c_funptr
            type(c_ptr), value :: handle
            type(c_funptr), value :: admissible
        end function rs_stepper_set_admissible
        integer(c_int) function rs_stepper_shortened_steps(handle, shortened) bind(C)
            import :: c_int, c_ptr
            type(c_ptr), value :: handle
            integer(c_int), intent(out) :: shortened
        end function rs_stepper_shortened_steps
        integer(c_int) function rs_stepper_set_breakpoints(handle, n, times) bind(C)
            import :: c_int, c_ptr, c_double
            type(c_ptr), value :: handle
            integer(c_int), value :: n
            real(c_double), intent(in) :: times(*)
        end function rs_stepper_set_breakpoints
        integer(c_int) function rs_stepper_set_error_entries(handle, n, weigh) bind(C)
            import :: c_int, c_ptr
            type(c_ptr), value :: handle
            integer(c_int), value :: n
            integer(c_int), intent(in) :: weigh(*)
        end function rs_stepper_set_error_entries
        integer(c_int) function rs_stepper_adaptive_stats(handle, rejected, h_smallest, &
                h_largest) bind(C)
            import :: c_int, c_ptr, c_double
            type(c_ptr), value :: handle
            integer(c_int), intent(out) :: rejected
            real(c_double), intent(out) :: h_smallest, h_largest
        end function rs_stepper_adaptive_stats
        integer(c_int) function rs_stepper_view(handle, path) bind(C)
            import :: c_int, c_char, c_ptr
            type(c_ptr), value :: handle
            character(kind=c_char), intent(in) :: path(*)
        end function rs_stepper_view
        integer(c_int) function rs_stepper_destroy(handle) bind(C)
            import :: c_int, c_ptr
            type(c_ptr), intent(inout) :: handle
        end function rs_stepper_destroy
        integer(c_int) function rs_petsc_apply_options(scene_options, user_options, errmsg, &
                errlen) bind(C)
            import :: c_int, c_char, c_ptr
            type(c_ptr), value :: scene_options, user_options
            character(kind=c_char), intent(out) :: errmsg(*)
            integer(c_int), value :: errlen
        end function rs_petsc_apply_options
        integer(c_int) function rs_petsc_unused_options(buffer, length) bind(C)
            import :: c_int, c_char
            character(kind=c_char), intent(out) :: buffer(*)
            integer(c_int), value :: length
        end function rs_petsc_unused_options
        integer(c_int) function rs_petsc_options_text(buffer, length) bind(C)
            import :: c_int, c_char
            character(kind=c_char), intent(out) :: buffer(*)
            integer(c_int), value :: length
        end function rs_petsc_options_text
        integer(c_int) function rs_petsc_log_begin() bind(C)
            import :: c_int
        end function rs_petsc_log_begin
        integer(c_int) function rs_petsc_event_count(name, count) bind(C)
            import :: c_int, c_char
            character(kind=c_char), intent(in) :: name(*)
            integer(c_int), intent(out) :: count
        end function rs_petsc_event_count
    end interface

    !> rs_stepper_advance's status when Newton failed after all cut-backs (RS_STEPPER_DIVERGED).
    integer(c_int), parameter :: stepper_diverged = 1
    !> Length of the message buffers handed to C.
    integer, parameter :: message_length = 1024

contains

    !> Create the stepper of a step problem with `n_state` state entries and `n_unknown`
    !> Newton unknowns. `row_ptr` (n_unknown + 1 entries) and `cols` are the 0-based CSR pattern
    !> of dF/dy, columns strictly increasing in each row. `predictor`, `update` and `poststep`
    !> may be `c_null_funptr` (defaults y = x_n and x_{n+1} = y, which need n_unknown =
    !> n_state). `traits`: the Newton settings, defaults that `petsc_options` and the command
    !> line override, and the solver flags (stepper_traits_t; the LU package is the chain LU, or
    !> PETSc's own with `native_lu`; Newton backtracks unless `full_newton`; one linear solve per
    !> step with `linear_step`). `blocks`: the unknowns in consecutive blocks (one per rod of a
    !> coupled system), solved by GMRES with block Jacobi (rs_stepper_create).
    subroutine rod_stepper_create(this, n_state, n_unknown, row_ptr, cols, residual, jacobian, &
            predictor, update, poststep, ctx, traits, err, owned, blocks)
        class(rod_stepper_t), intent(inout) :: this
        integer, intent(in) :: n_state, n_unknown
        integer, intent(in) :: row_ptr(:), cols(:)
        ! By value: a c_funloc(...) constant passed by reference would land in .rodata with an
        ! absolute relocation (gfortran), i.e. a text relocation in PIE executables.
        type(c_funptr), value :: residual, jacobian, predictor, update, poststep
        type(c_ptr), value :: ctx
        type(stepper_traits_t), intent(in) :: traits
        type(error_t), allocatable, intent(out) :: err
        !> A system shared by all ranks (rs_stepper_create): this rank's 0-based ranges
        !> [state_lo, state_hi, unknown_lo, unknown_hi).
        integer, intent(in), optional :: owned(4)
        integer, intent(in), optional :: blocks(:)
        integer(c_int), target :: owned_c(4)
        integer(c_int), allocatable, target :: blocks_c(:)
        type(c_ptr) :: owned_ptr, blocks_ptr
        character(kind=c_char) :: message(message_length)
        character(len=:), allocatable :: problem
        integer(c_int) :: ierr

        call this%destroy()
        ! C cannot see the array lengths: check them here, the pattern itself is checked in C.
        if (n_unknown < 1 .or. size(row_ptr) /= n_unknown + 1) then
            problem = 'row_ptr has ' // str(size(row_ptr)) // ' entries; n_unknown + 1 = ' // &
                str(n_unknown + 1) // ' expected'
            RS_SET_ERROR(err, 'rod_stepper_create', problem)
            return
        end if
        if (row_ptr(n_unknown + 1) /= size(cols)) then
            problem = 'cols has ' // str(size(cols)) // ' entries; the pattern (row_ptr) has ' // &
                str(row_ptr(n_unknown + 1))
            RS_SET_ERROR(err, 'rod_stepper_create', problem)
            return
        end if
        message = c_null_char
        owned_ptr = c_null_ptr
        if (present(owned)) then
            owned_c = int(owned, c_int)
            owned_ptr = c_loc(owned_c)
        end if
        blocks_ptr = c_null_ptr
        allocate(blocks_c(0))
        if (present(blocks)) then
            blocks_c = int(blocks, c_int)
            if (size(blocks_c) > 1) blocks_ptr = c_loc(blocks_c)
        end if
        ierr = rs_stepper_create(this%handle, int(n_state, c_int), int(n_unknown, c_int), &
            int(row_ptr, c_int), int(cols, c_int), residual, jacobian, predictor, update, &
            poststep, ctx, traits, owned_ptr, int(size(blocks_c), c_int), blocks_ptr, message, &
            int(message_length, c_int))
        if (ierr /= 0) then
            this%handle = c_null_ptr
            RS_SET_ERROR(err, 'rod_stepper_create', from_c_string(message))
            return
        end if
        this%n_state = n_state
    end subroutine rod_stepper_create

    !> A system shared by the ranks: before each residual, Jacobian, predictor and update only
    !> the 0-based entries `state_entries` of the state and `unknown_entries` of the unknowns
    !> are gathered (the rods this rank's rows read, rs_system_rod_system%needed_entries).
    subroutine rod_stepper_set_needed(this, state_entries, unknown_entries, err)
        class(rod_stepper_t), intent(inout) :: this
        integer, intent(in) :: state_entries(:), unknown_entries(:)
        type(error_t), allocatable, intent(out) :: err
        character(kind=c_char) :: message(message_length)
        integer(c_int) :: ierr
        message = c_null_char
        ierr = rs_stepper_set_needed(this%handle, int(size(state_entries), c_int), &
            int(state_entries, c_int), int(size(unknown_entries), c_int), &
            int(unknown_entries, c_int), message, int(message_length, c_int))
        if (ierr /= 0) then
            RS_SET_ERROR(err, 'rod_stepper_set_needed', from_c_string(message))
        end if
    end subroutine rod_stepper_set_needed

    !> Advance `x` from X(t_n) to X(t_n + dt) in substeps: each tries the rest of dt and is
    !> halved by the TS when Newton fails, up to max_cutbacks times. Outputs: the number of
    !> accepted substeps, their halvings and Newton (SNES) iterations, and the final residual
    !> norm. When Newton still fails, `err` says at which time, with how small a step and
    !> why, `x` holds the last good state (that time), and `diverged` (if present) is true.
    subroutine rod_stepper_advance(this, t_n, dt, x, substeps, cutbacks, newton_its, fnorm, err, &
            diverged)
        class(rod_stepper_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, dt
        real(rk), intent(inout) :: x(:)
        integer, intent(out) :: substeps, cutbacks, newton_its
        real(rk), intent(out) :: fnorm
        type(error_t), allocatable, intent(out) :: err
        logical, intent(out), optional :: diverged
        character(kind=c_char) :: message(message_length)
        integer(c_int) :: ierr, substeps_c, cutbacks_c, its_c
        real(c_double) :: fnorm_c

        substeps = 0
        cutbacks = 0
        newton_its = 0
        fnorm = 0.0_rk
        if (present(diverged)) diverged = .false.
        if (.not. this%is_created()) then
            RS_SET_ERROR(err, 'rod_stepper_advance', 'the stepper was not created')
            return
        end if
        if (size(x) /= this%n_state) then
            RS_SET_ERROR(err, 'rod_stepper_advance', 'x has ' // str(size(x)) // ' entries, not ' // str(this%n_state))
            return
        end if
        message = c_null_char
        ierr = rs_stepper_advance(this%handle, real(t_n, c_double), real(dt, c_double), x, &
            substeps_c, cutbacks_c, its_c, fnorm_c, message, int(message_length, c_int))
        substeps = int(substeps_c)
        cutbacks = int(cutbacks_c)
        newton_its = int(its_c)
        fnorm = real(fnorm_c, rk)
        if (ierr /= 0) then
            if (present(diverged)) diverged = ierr == stepper_diverged
            RS_SET_ERROR(err, 'rod_stepper_advance', from_c_string(message))
        end if
    end subroutine rod_stepper_advance

    !> Factor the Jacobian `values` (in the order of the stepper's pattern); `singular`: a zero
    !> pivot was met (a limit or bifurcation point exactly, or an unsupported rod).
    subroutine rod_stepper_factor(this, values, singular, err)
        class(rod_stepper_t), intent(inout) :: this
        real(rk), intent(in) :: values(:)
        logical, intent(out) :: singular
        type(error_t), allocatable, intent(out) :: err
        character(kind=c_char) :: message(message_length)
        integer(c_int) :: ierr, singular_c
        singular = .false.
        message = c_null_char
        ierr = rs_stepper_factor(this%handle, values, singular_c, message, &
            int(message_length, c_int))
        if (ierr /= 0) then
            RS_SET_ERROR(err, 'rod_stepper_factor', from_c_string(message))
            return
        end if
        singular = singular_c /= 0
    end subroutine rod_stepper_factor

    !> sol = J^{-1} rhs with the last factorization; `failed`: the linear solve diverged.
    subroutine rod_stepper_solve(this, rhs, sol, failed, err)
        class(rod_stepper_t), intent(inout) :: this
        real(rk), intent(in) :: rhs(:)
        real(rk), intent(out) :: sol(:)
        logical, intent(out) :: failed
        type(error_t), allocatable, intent(out) :: err
        character(kind=c_char) :: message(message_length)
        integer(c_int) :: ierr, failed_c
        failed = .false.
        message = c_null_char
        ierr = rs_stepper_solve(this%handle, rhs, sol, failed_c, message, &
            int(message_length, c_int))
        if (ierr /= 0) then
            RS_SET_ERROR(err, 'rod_stepper_solve', from_c_string(message))
            return
        end if
        failed = failed_c /= 0
    end subroutine rod_stepper_solve

    !> SNES tolerances and limits, the maximum cut-backs and the solver chain ("snes newtonls
    !> linesearch bt ksp preonly pc lu solver mumps") after all options were applied.
    subroutine rod_stepper_solver_settings(this, atol, rtol, stol, max_it, max_funcs, &
            max_cutbacks, types, err)
        class(rod_stepper_t), intent(in) :: this
        real(rk), intent(out) :: atol, rtol, stol
        integer, intent(out) :: max_it, max_funcs, max_cutbacks
        character(len=:), allocatable, intent(out) :: types
        type(error_t), allocatable, intent(out) :: err
        character(kind=c_char) :: buffer(256)
        real(c_double) :: atol_c, rtol_c, stol_c
        integer(c_int) :: max_it_c, max_funcs_c, max_cutbacks_c, ierr

        types = ''
        atol = 0.0_rk
        rtol = 0.0_rk
        stol = 0.0_rk
        max_it = 0
        max_funcs = 0
        max_cutbacks = 0
        if (.not. this%is_created()) then
            RS_SET_ERROR(err, 'rod_stepper_solver_settings', 'the stepper was not created')
            return
        end if
        buffer = c_null_char
        ierr = rs_stepper_solver_settings(this%handle, atol_c, rtol_c, stol_c, max_it_c, &
            max_funcs_c, max_cutbacks_c, buffer, int(size(buffer), c_int))
        RS_CHECK_PETSC(int(ierr), err, 'rod_stepper_solver_settings', 'SNESGetTolerances')
        atol = real(atol_c, rk)
        rtol = real(rtol_c, rk)
        stol = real(stol_c, rk)
        max_it = int(max_it_c)
        max_funcs = int(max_funcs_c)
        max_cutbacks = int(max_cutbacks_c)
        types = from_c_string(buffer)
    end subroutine rod_stepper_solver_settings

    !> TSView of the stepper (the rodmid line, then SNES, KSP, PC) into `path`; '' for stdout.
    subroutine rod_stepper_view(this, path, err)
        class(rod_stepper_t), intent(in) :: this
        character(len=*), intent(in) :: path
        type(error_t), allocatable, intent(out) :: err
        integer(c_int) :: ierr
        if (.not. this%is_created()) then
            RS_SET_ERROR(err, 'rod_stepper_view', 'the stepper was not created')
            return
        end if
        ierr = rs_stepper_view(this%handle, to_c_string(path))
        RS_CHECK_PETSC(int(ierr), err, 'rod_stepper_view', 'TSView')
    end subroutine rod_stepper_view

    !> Since creation: Jacobians factored, steps accepted at the rounding floor and (optional)
    !> Newton steps the feasible-step filter shortened.
    subroutine rod_stepper_run_stats(this, jacobians, floor_steps, shortened)
        class(rod_stepper_t), intent(in) :: this
        integer, intent(out) :: jacobians, floor_steps
        integer, intent(out), optional :: shortened
        integer(c_int) :: counts(3)
        counts = 0
        if (c_associated(this%handle)) then
            if (rs_stepper_run_stats(this%handle, counts(1), counts(2)) /= 0) counts(1:2) = 0
            if (rs_stepper_shortened_steps(this%handle, counts(3)) /= 0) counts(3) = 0
        end if
        jacobians = int(counts(1))
        floor_steps = int(counts(2))
        if (present(shortened)) shortened = int(counts(3))
    end subroutine rod_stepper_run_stats

    !> Newton steps shortened until `admissible` (a bind(C) function of the rs_cb_admissible
    !> interface, admissible_callback_t) admits their full step.
    subroutine rod_stepper_set_admissible(this, admissible, err)
        class(rod_stepper_t), intent(inout) :: this
        type(c_funptr), value :: admissible
        type(error_t), allocatable, intent(out) :: err
        integer(c_int) :: ierr
        ierr = rs_stepper_set_admissible(this%handle, admissible)
        if (ierr /= 0) then
            RS_SET_ERROR(err, 'rod_stepper_set_admissible', 'the feasible-step filter could not be set (code ' // str(int(ierr)) // ')')
        end if
    end subroutine rod_stepper_set_admissible

    !> The times an adaptive stepper's steps hit exactly (load kinks, scene_time_kinks).
    subroutine rod_stepper_set_breakpoints(this, times, err)
        class(rod_stepper_t), intent(inout) :: this
        real(rk), intent(in) :: times(:)
        type(error_t), allocatable, intent(out) :: err
        real(c_double) :: copy(max(size(times), 1))
        integer(c_int) :: ierr
        copy = 0.0_c_double
        copy(1:size(times)) = real(times, c_double)
        ierr = rs_stepper_set_breakpoints(this%handle, int(size(times), c_int), copy)
        if (ierr /= 0) then
            RS_SET_ERROR(err, 'rod_stepper_set_breakpoints', 'the load kinks could not be set')
        end if
    end subroutine rod_stepper_set_breakpoints

    !> The state entries (weigh, the whole state) whose local error an adaptive stepper
    !> controls (rs_formulations_formulation's error_entries).
    subroutine rod_stepper_set_error_entries(this, weigh, err)
        class(rod_stepper_t), intent(inout) :: this
        logical, intent(in) :: weigh(:)
        type(error_t), allocatable, intent(out) :: err
        integer(c_int) :: ierr
        ierr = rs_stepper_set_error_entries(this%handle, int(size(weigh), c_int), &
            merge(1_c_int, 0_c_int, weigh))
        if (ierr /= 0) then
            RS_SET_ERROR(err, 'rod_stepper_set_error_entries', 'the controlled entries could not be set')
        end if
    end subroutine rod_stepper_set_error_entries

    !> Since creation, for an adaptive stepper: steps the error control rejected, the smallest
    !> and largest accepted steps (0 before any).
    subroutine rod_stepper_adaptive_stats(this, rejected, h_smallest, h_largest)
        class(rod_stepper_t), intent(in) :: this
        integer, intent(out) :: rejected
        real(rk), intent(out) :: h_smallest, h_largest
        integer(c_int) :: count
        real(c_double) :: smallest, largest
        count = 0
        smallest = 0.0_c_double
        largest = 0.0_c_double
        if (c_associated(this%handle)) then
            if (rs_stepper_adaptive_stats(this%handle, count, smallest, largest) /= 0) count = 0
        end if
        rejected = int(count)
        h_smallest = real(smallest, rk)
        h_largest = real(largest, rk)
    end subroutine rod_stepper_adaptive_stats

    logical function rod_stepper_is_created(this)
        class(rod_stepper_t), intent(in) :: this
        rod_stepper_is_created = c_associated(this%handle)
    end function rod_stepper_is_created

    subroutine rod_stepper_destroy(this)
        class(rod_stepper_t), intent(inout) :: this
        integer(c_int) :: ierr
        if (c_associated(this%handle)) ierr = rs_stepper_destroy(this%handle)
        this%handle = c_null_ptr
        this%n_state = 0
    end subroutine rod_stepper_destroy

    !> Layer the run's PETSc options (DESIGN.md §3): `user_options` (the input's petsc_options)
    !> replaces the petsc_options layer, `scene_options` are scene values below it; the command
    !> line stays on top. An absent argument leaves its layer alone. Call it on every rank
    !> before the first stepper is created; it is not collective.
    subroutine petsc_apply_options(scene_options, user_options, err)
        character(len=*), intent(in), optional :: scene_options, user_options
        type(error_t), allocatable, intent(out) :: err
        character(kind=c_char), allocatable, target :: scene_c(:), user_c(:)
        character(kind=c_char) :: message(message_length)
        type(c_ptr) :: scene_p, user_p
        integer(c_int) :: ierr
        scene_p = c_null_ptr
        user_p = c_null_ptr
        if (present(scene_options)) then
            scene_c = to_c_string(scene_options)
            scene_p = c_loc(scene_c)
        end if
        if (present(user_options)) then
            user_c = to_c_string(user_options)
            user_p = c_loc(user_c)
        end if
        message = c_null_char
        ierr = rs_petsc_apply_options(scene_p, user_p, message, int(message_length, c_int))
        if (ierr /= 0) then
            RS_SET_ERROR(err, 'petsc_apply_options', from_c_string(message))
        end if
    end subroutine petsc_apply_options

    !> Every option in PETSc's database ("-name value ..."), for the output file (DESIGN.md §3:
    !> "the values actually used are recorded"); '' if PETSc cannot list them.
    function petsc_options_text() result(text)
        character(len=:), allocatable :: text
        character(kind=c_char), allocatable :: buffer(:)
        integer(c_int) :: n
        allocate(buffer(4096))
        n = rs_petsc_options_text(buffer, int(size(buffer), c_int))
        if (n >= size(buffer)) then
            deallocate(buffer)
            allocate(buffer(n + 1))
            n = rs_petsc_options_text(buffer, int(size(buffer), c_int))
        end if
        if (n < 0) then
            text = ''
        else
            text = from_c_string(buffer)
        end if
    end function petsc_options_text

    !> The options given on the command line or in a scene's petsc_options that nothing has
    !> read ('' if none): misspelled, or for a solver the run does not use.
    function petsc_unused_options() result(text)
        character(len=:), allocatable :: text
        character(kind=c_char) :: buffer(4096)
        text = ''
        if (rs_petsc_unused_options(buffer, int(size(buffer), c_int)) > 0) &
            text = from_c_string(buffer)
    end function petsc_unused_options

    !> Start PETSc's event logging (as -log_view does), e.g. to count factorizations.
    subroutine petsc_log_begin(err)
        type(error_t), allocatable, intent(out) :: err
        integer(c_int) :: ierr
        ierr = rs_petsc_log_begin()
        RS_CHECK_PETSC(int(ierr), err, 'petsc_log_begin', 'PetscLogDefaultBegin')
    end subroutine petsc_log_begin

    !> How often PETSc's event `name` (e.g. 'MatLUFactorSym') ran in the current logging stage
    !> since logging began (`petsc_log_begin` or -log_view); an error if logging is off.
    subroutine petsc_event_count(name, count, err)
        character(len=*), intent(in) :: name
        integer, intent(out) :: count
        type(error_t), allocatable, intent(out) :: err
        integer(c_int) :: ierr, count_c
        ierr = rs_petsc_event_count(to_c_string(name), count_c)
        count = int(count_c)
        if (ierr == 1) then
            RS_SET_ERROR(err, 'petsc_event_count', 'PETSc event logging is off (petsc_log_begin, -log_view)')
        else if (ierr /= 0) then
            call set_error(err, 'PETSc call PetscLogEventGetPerfInfo failed with error code ' // &
                str(int(ierr)), 'petsc_event_count', __FILE__, __LINE__)
        end if
    end subroutine petsc_event_count

end module rs_solver_rod_stepper
