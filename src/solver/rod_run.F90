#include "rs_macros.h"
!> Runs the rods of a scene through time (DESIGN.md §3 and §5): each rank takes its share of
!> the rods, builds each rod's formulation, solves it with its own sequential rodmid stepper on
!> PETSC_COMM_SELF (no communication in the time loop), and keeps the records for the output.
!>
!> PETSc calls back into the formulation through `bind(C)` procedures that receive a plain,
!> non-polymorphic context holding a pointer to the formulation (DESIGN.md §3: a polymorphic
!> dummy cannot pass through PETSc); they wrap the raw arrays and call the type-bound kernels.
module rs_solver_rod_run
    use, intrinsic :: iso_c_binding, only: c_int, c_double, c_ptr, c_funloc, c_loc, c_f_pointer
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_core_logger, only: log_info
    use rs_core_strings, only: str, str_significant
    use rs_core_timer, only: wall_time
    use rs_model_scene, only: scene_t
    use rs_model_rod_history, only: rod_history_t
    use rs_formulations_formulation, only: rod_formulation_t, state_valid
    use rs_formulations_factory, only: create_formulation
    use rs_solver_rod_stepper, only: rod_stepper_t
    implicit none
    private

    public :: run_rod, step_count

    !> What PETSc's callbacks receive: the formulation and the vector sizes.
    type :: callback_context_t
        class(rod_formulation_t), pointer :: formulation => null()
        integer :: n_state = 0
        integer :: n_unknown = 0
        integer :: n_values = 0
        !> End of the last accepted (sub)step: where a failed step leaves the state.
        real(rk) :: t_reached = 0.0_rk
    end type callback_context_t

    !> Seconds between two progress lines of one rod.
    real(rk), parameter :: progress_interval = 5.0_rk

contains

    !> Number of steps of the scene's time grid (the last one may be shorter).
    pure integer function step_count(scene)
        type(scene_t), intent(in) :: scene
        step_count = max(1, ceiling(scene%time%t_end / scene%time%dt - 1.0e-9_rk))
    end function step_count

    !> Run rod `rod_index` from t = 0 to t_end and fill its history. On a solver failure the
    !> history ends with the last good state and `err` says where and why.
    subroutine run_rod(scene, rod_index, history, err)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rod_index
        type(rod_history_t), intent(inout) :: history
        type(error_t), allocatable, intent(out) :: err
        class(rod_formulation_t), allocatable, target :: formulation
        type(callback_context_t), target :: context
        type(rod_stepper_t) :: stepper
        integer, allocatable :: row_ptr(:), cols(:)
        real(rk), allocatable :: x(:)
        real(rk) :: t_n, h, fnorm, started, last_report, elapsed, t_recorded
        integer :: n, n_steps, stride, substeps, cutbacks, iterations, total_iterations
        integer :: total_cutbacks

        call create_formulation(scene%rods(rod_index)%formulation, formulation, err)
        RS_RETURN_IF_ERROR(err)
        call formulation%init(scene, rod_index, err)
        RS_RETURN_IF_ERROR(err)
        call log_info(formulation%describe())

        n_steps = step_count(scene)
        stride = scene%output%stride
        call formulation%init_history(history, n_steps / stride + 2)
        allocate(x(formulation%n_state()))
        call formulation%initial_state(x)
        call formulation%record(history, 0.0_rk, x)
        t_recorded = 0.0_rk

        call formulation%jacobian_pattern(row_ptr, cols)
        context%formulation => formulation
        context%n_state = formulation%n_state()
        context%n_unknown = formulation%n_unknown()
        context%n_values = size(cols)
        call stepper%create(context%n_state, context%n_unknown, row_ptr, cols, &
            c_funloc(residual_callback), c_funloc(jacobian_callback), &
            c_funloc(predictor_callback), c_funloc(update_callback), c_funloc(poststep_callback), &
            c_loc(context), scene%solver%newton_atol, scene%solver%newton_rtol, &
            scene%solver%max_newton, scene%solver%max_cutbacks, err)
        RS_RETURN_IF_ERROR(err)

        started = wall_time()
        last_report = started
        total_iterations = 0
        total_cutbacks = 0
        do n = 1, n_steps
            t_n = real(n - 1, rk) * scene%time%dt
            h = min(scene%time%dt, scene%time%t_end - t_n)
            call stepper%advance(t_n, h, x, substeps, cutbacks, iterations, fnorm, err)
            total_iterations = total_iterations + iterations
            total_cutbacks = total_cutbacks + cutbacks
            if (allocated(err)) then
                ! The stepper left x at the last good state (after any accepted substeps of
                ! this step); record it so it is written.
                if (context%t_reached > t_recorded) &
                    call formulation%record(history, context%t_reached, x)
                call stepper%destroy()
                return
            end if
            if (n == n_steps .and. formulation%wants_endpoint_solve()) then
                ! Quasistatics (DESIGN.md §3): the midpoint steps are equilibria at the mid
                ! loads; the last record is the equilibrium at the final load itself.
                call formulation%set_endpoint_solve(.true., scene%time%t_end)
                call stepper%advance(t_n, h, x, substeps, cutbacks, iterations, fnorm, err)
                call formulation%set_endpoint_solve(.false., scene%time%t_end)
                total_iterations = total_iterations + iterations
                total_cutbacks = total_cutbacks + cutbacks
                if (allocated(err)) then
                    call formulation%record(history, context%t_reached, x)
                    call stepper%destroy()
                    err%message = 'endpoint equilibrium at t = ' // str(scene%time%t_end) // &
                        ': ' // err%message
                    return
                end if
                call log_info('  ' // history%name // ': endpoint equilibrium at t = ' // &
                    str(scene%time%t_end) // ' in ' // str(iterations) // ' Newton iterations')
            end if
            if (mod(n, stride) == 0 .or. n == n_steps) then
                ! n dt rather than t_n + h, so that stored times are the grid's own values.
                t_recorded = min(real(n, rk) * scene%time%dt, scene%time%t_end)
                call formulation%record(history, t_recorded, x)
            end if
            if (wall_time() - last_report >= progress_interval .or. n == n_steps) then
                last_report = wall_time()
                call log_info('  ' // history%name // ': t = ' // str(t_n + h) // ', step ' // &
                    str(n) // '/' // str(n_steps) // ', Newton iterations ' // &
                    str(total_iterations) // ', cut-backs ' // str(total_cutbacks) // ', ' // &
                    str_significant(last_report - started, 3) // ' s')
            end if
        end do
        call stepper%destroy()
        ! The summary line is also what tests/bench/ reads (time loop only, output excluded).
        elapsed = wall_time() - started
        call log_info('  ' // history%name // ': ' // str(n_steps) // ' steps, ' // &
            str(total_iterations) // ' Newton iterations, ' // str(total_cutbacks) // &
            ' cut-backs; time loop ' // str_significant(elapsed, 4) // ' s, per step ' // &
            str_significant(elapsed / n_steps, 4) // ' s, per Newton iteration ' // &
            str_significant(elapsed / max(1, total_iterations), 4) // ' s')
    end subroutine run_rod

    ! ---- PETSc callbacks (src/solver/rod_stepper.c) -------------------------------------------

    function residual_callback(ctx, t_n, h, x_n, y, f) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y, f
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        type(callback_context_t), pointer :: context
        real(rk), pointer :: x_n_(:), y_(:), f_(:)
        integer :: state
        call c_f_pointer(ctx, context)
        call c_f_pointer(x_n, x_n_, [context%n_state])
        call c_f_pointer(y, y_, [context%n_unknown])
        call c_f_pointer(f, f_, [context%n_unknown])
        call context%formulation%step_residual(t_n, h, x_n_, y_, f_, state)
        status = int(state, c_int)
    end function residual_callback

    function jacobian_callback(ctx, t_n, h, x_n, y, values) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y, values
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        type(callback_context_t), pointer :: context
        real(rk), pointer :: x_n_(:), y_(:), values_(:)
        integer :: state
        call c_f_pointer(ctx, context)
        call c_f_pointer(x_n, x_n_, [context%n_state])
        call c_f_pointer(y, y_, [context%n_unknown])
        call c_f_pointer(values, values_, [context%n_values])
        call context%formulation%step_jacobian(t_n, h, x_n_, y_, values_, state)
        status = int(state, c_int)
    end function jacobian_callback

    function predictor_callback(ctx, t_n, h, x_n, y) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        type(callback_context_t), pointer :: context
        real(rk), pointer :: x_n_(:), y_(:)
        call c_f_pointer(ctx, context)
        call c_f_pointer(x_n, x_n_, [context%n_state])
        call c_f_pointer(y, y_, [context%n_unknown])
        call context%formulation%predictor(t_n, h, x_n_, y_)
        status = state_valid
    end function predictor_callback

    function update_callback(ctx, t_n, h, x_n, y, x_1) result(status) bind(C)
        type(c_ptr), value :: ctx, x_n, y, x_1
        real(c_double), value :: t_n, h
        integer(c_int) :: status
        type(callback_context_t), pointer :: context
        real(rk), pointer :: x_n_(:), y_(:), x_1_(:)
        call c_f_pointer(ctx, context)
        call c_f_pointer(x_n, x_n_, [context%n_state])
        call c_f_pointer(y, y_, [context%n_unknown])
        call c_f_pointer(x_1, x_1_, [context%n_state])
        call context%formulation%update(t_n, h, x_n_, y_, x_1_)
        status = state_valid
    end function update_callback

    function poststep_callback(ctx, t_n, h, x_n, x_1, newton_iterations, fnorm) result(status) &
            bind(C)
        type(c_ptr), value :: ctx, x_n, x_1
        real(c_double), value :: t_n, h, fnorm
        integer(c_int), value :: newton_iterations
        integer(c_int) :: status
        type(callback_context_t), pointer :: context
        real(rk), pointer :: x_n_(:), x_1_(:)
        call c_f_pointer(ctx, context)
        call c_f_pointer(x_n, x_n_, [context%n_state])
        call c_f_pointer(x_1, x_1_, [context%n_state])
        call context%formulation%accept_step(t_n, h, x_n_, x_1_, int(newton_iterations), fnorm)
        context%t_reached = t_n + h
        status = state_valid
    end function poststep_callback

end module rs_solver_rod_run
