!> rodsolve: nonlinear dynamics and statics of Cosserat rods.
!>
!> The thin main program of DESIGN.md §2 (STYLE.md item 1): read the command line, start PETSc
!> and MPI, read and validate the scene, run, write, finalize. Everything else lives in the
!> libraries; errors come back here as values and leave through rs_parallel_abort.
program rodsolve
    use, intrinsic :: iso_fortran_env, only: output_unit
    use rs_core_error, only: error_t, error_list_t, exit_input_error, exit_run_error
    use rs_core_logger, only: logger_init, log_info, log_level_from_name
    use rs_core_strings, only: str
    use rs_core_version, only: rodsolve_version, rodsolve_git_commit
    use rs_model_scene, only: scene_t
    use rs_parallel_mpi_env, only: world_rank, world_size, mpi_library_version, barrier, &
        any_rank_true, broadcast_text
    use rs_parallel_abort, only: stop_all, set_cleanup
    use rs_parallel_metis, only: metis_version
    use rs_io_cli, only: cli_t, parse_command_line, usage_text
    use rs_io_input_file, only: load_scene
    use rs_io_scene_writer, only: resolved_scene_text
    use rs_formulations_plan, only: scene_plan_text
    use rs_formulations_memory_estimate, only: memory_refusal
    use rs_io_input_reference, only: input_reference_markdown
    use rs_model_capability_matrix, only: capability_matrix_markdown
    use rs_formulations_registry, only: registered_capabilities
    use rs_io_hdf5_info, only: hdf5_version
    use rs_solver_petsc_env, only: petsc_initialize, petsc_finalize, petsc_version, mumps_version
    use rs_app_run_scene, only: run_scene, coupled_system_plans
    use rs_app_run_sweep, only: run_sweep, merge_sweep
    use rs_io_sweep, only: sweep_member_count
    use rs_io_output_guard, only: output_lock_t, check_output_target
    use rs_io_hdf5_file, only: hdf5_file_t
    use rs_solver_rod_stepper, only: petsc_unused_options
    use rs_core_logger, only: log_warning
    use rs_core_interrupt, only: install_interrupt_handlers
    implicit none

    type(cli_t) :: cli
    type(error_t), allocatable :: err
    type(error_list_t) :: input_errors
    type(scene_t) :: scene
    !> The output path's lock, held by rank 0 while a run or a merge writes it.
    type(output_lock_t) :: output_lock

    cli = command_line()
    call petsc_initialize(cli%program, cli%petsc_args, err)
    if (allocated(err)) call stop_all(exit_run_error, 'rodsolve: ' // err%describe())
    call set_cleanup(petsc_finalize)
    ! After PETSc's own handlers, which abort: SIGTERM and SIGINT end a run cleanly.
    if (.not. install_interrupt_handlers()) call log_warning('rodsolve: cannot catch SIGTERM ' // &
        'and SIGINT: a run stopped by its job''s time limit keeps only its last flush')
    call logger_init(world_rank(), quiet=cli%quiet)
    if (len(cli%error) > 0) call stop_all(exit_input_error, cli%error // new_line('a') // usage_text())

    select case (cli%action)
    case ('help')
        call print_root(usage_text())
    case ('version')
        call print_root(version_text())
    case ('reference')
        call print_root(input_reference_markdown())
    case ('capabilities')
        call print_root(capability_matrix_markdown(registered_capabilities()))
    case ('check', 'run', 'merge')
        call load_scene(cli%scene_file, scene, input_errors)
        if (input_errors%count > 0) call stop_all(exit_input_error, input_errors%joined() // &
            new_line('a') // 'rodsolve: ' // str(input_errors%count) // ' error(s) in ' // &
            cli%scene_file // '; nothing was run')
        call logger_init(world_rank(), level=log_level_from_name(trim(scene%run%log_level)), &
            quiet=cli%quiet)
        if (cli%action == 'check') then
            call print_root(resolved_scene_text(scene) // &
                scene_plan_text(scene, world_size()) // &
                plan_comment(coupled_system_plans(scene, err)))
            if (allocated(err)) call stop_all(exit_input_error, 'rodsolve: ' // err%describe())
            call log_info('rodsolve: ' // cli%scene_file // ' is valid (' // str(size(scene%rods)) // &
                ' rod(s)); nothing was run (--check-input)')
        else
            if (cli%action == 'run') call refuse_what_will_not_fit(cli%scene_file, scene)
            call guard_output(cli%action, cli%scene_file, scene)
            if (cli%action == 'merge') then
                ! A killed sweep: its finished members into its result file (rank 0; DESIGN.md §7).
                if (sweep_member_count(scene) == 0) call stop_all(exit_input_error, 'rodsolve: ' // &
                    cli%scene_file // ' has no &sweep group: there is nothing to merge')
                if (world_rank() == 0) call merge_sweep(scene, full_command_line(), err, &
                    verify=.true.)
                call barrier()
            else if (sweep_member_count(scene) > 0) then
                call run_sweep(scene, full_command_line(), err)
            else
                call run_scene(scene, full_command_line(), err)
            end if
            if (world_rank() == 0) call report_unused_options(trim(scene%output%path))
            call output_lock%release()
            if (allocated(err)) call stop_all(err%exit_status, 'rodsolve: ' // err%describe())
        end if
    end select
    call stop_all(0)

contains

    !> `text` as comment lines of the plan ('!   ' before each line).
    function plan_comment(text) result(comment)
        character(len=*), intent(in) :: text
        character(len=:), allocatable :: comment
        integer :: start, finish
        comment = ''
        start = 1
        do while (start <= len(text))
            finish = index(text(start:), new_line('a'))
            if (finish == 0) finish = len(text) - start + 2
            if (finish > 1) comment = comment // '!   ' // text(start:start + finish - 2) // &
                new_line('a')
            start = start + finish
        end do
    end function plan_comment

    !> PETSc options the user gave that nothing read (a misspelling, or an option of a solver
    !> the run does not use): a warning in the log and the result file's root attribute
    !> `unused_petsc_options` (issue 21 item 19).
    subroutine report_unused_options(path)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: unused
        type(hdf5_file_t) :: file
        type(error_t), allocatable :: file_err
        logical :: exists
        unused = petsc_unused_options()
        if (len(unused) == 0) return
        call log_warning('rodsolve: PETSc options given but never used (misspelled, or for a ' // &
            'solver this run does not use): ' // unused)
        inquire(file=path, exist=exists)
        if (.not. exists) return
        call file%open(path, file_err)
        if (.not. allocated(file_err)) call file%write_attribute('/', 'unused_petsc_options', &
            unused, file_err)
        if (allocated(file_err)) deallocate(file_err)
        call file%close(file_err)
    end subroutine report_unused_options

    !> Before anything is written: rank 0 takes the output path's lock and checks what is
    !> there (rs_io_output_guard); if either fails, every rank stops with rank 0's message and
    !> the path is left as it was.
    subroutine guard_output(action, scene_file, scene)
        character(len=*), intent(in) :: action, scene_file
        type(scene_t), intent(in) :: scene
        type(error_t), allocatable :: refused
        character(len=:), allocatable :: path, warning, message
        path = trim(scene%output%path)
        message = ''
        if (world_rank() == 0) then
            call output_lock%acquire(path, 'a rodsolve ' // trim(action) // ' of ' // scene_file, &
                refused, warning)
            if (len(warning) > 0) call log_warning('rodsolve: ' // warning)
            if (.not. allocated(refused)) call check_output_target(path, scene_file, refused)
            if (allocated(refused)) message = 'rodsolve: ' // refused%describe()
        end if
        if (.not. any_rank_true(len(message) > 0)) return
        call output_lock%release()
        call broadcast_text(message, 0)
        call stop_all(exit_run_error, message)
    end subroutine guard_output

    !> Before anything is allocated or written: a run whose estimated memory exceeds what is
    !> available is refused (issue 21 item 17; rs_formulations_memory_estimate). Rank 0's
    !> verdict, from its machine, holds for all ranks.
    subroutine refuse_what_will_not_fit(scene_file, scene)
        character(len=*), intent(in) :: scene_file
        type(scene_t), intent(in) :: scene
        character(len=:), allocatable :: refusal
        refusal = ''
        if (world_rank() == 0) refusal = memory_refusal(scene, world_size())
        call broadcast_text(refusal, 0)
        if (len(refusal) > 0) call stop_all(exit_input_error, 'rodsolve: ' // scene_file // &
            ': ' // refusal // '; nothing was run')
    end subroutine refuse_what_will_not_fit

    !> The command line, parsed (rodsolve's flags, the scene, PETSc's options).
    function command_line() result(parsed)
        type(cli_t) :: parsed
        character(len=4096), allocatable :: args(:)
        character(len=4096) :: program
        integer :: i
        call get_command_argument(0, program)
        allocate(args(command_argument_count()))
        do i = 1, size(args)
            call get_command_argument(i, args(i))
        end do
        parsed = parse_command_line(program, args)
    end function command_line

    !> The command line as typed, for the output file.
    function full_command_line() result(text)
        character(len=:), allocatable :: text
        integer :: length
        call get_command(length=length)
        allocate(character(len=length) :: text)
        if (length > 0) call get_command(text)
    end function full_command_line

    !> Print `text` once, from rank 0.
    subroutine print_root(text)
        character(len=*), intent(in) :: text
        if (world_rank() == 0) then
            write(output_unit, '(a)') text
            flush(output_unit)
        end if
    end subroutine print_root

    !> rodsolve's version and commit, and the versions of the libraries it is linked against.
    function version_text() result(text)
        character(len=:), allocatable :: text
        character(len=*), parameter :: nl = new_line('a')
        text = 'rodsolve ' // rodsolve_version // ' (git ' // rodsolve_git_commit // ')' // nl // &
            '  PETSc  ' // petsc_version() // nl // &
            '  MUMPS  ' // mumps_version() // nl // &
            '  HDF5   ' // hdf5_version() // nl // &
            '  MPI    ' // mpi_library_version() // ' (' // str(world_size()) // ' rank(s))' // nl // &
            '  METIS  ' // metis_version()
    end function version_text

end program rodsolve
