#include "rs_macros.h"
!> The run of a validated scene (DESIGN.md §5 and §7): systems (one rod, or the rods joints
!> couple; rs_model_coupling) are dealt to ranks round-robin and
!> every rank steps its systems together, one step of the time grid at a time, with no
!> communication between flushes. Every `flush_every` steps the ranks meet at the result file
!> (parallel HDF5 when there are several): it is extended, each rank writes the new records and
!> the checkpoint of its own rods, and it is flushed, so a killed run leaves a readable file with
!> every record up to the last flush; `restart_from` continues from that checkpoint. A rod that fails stops only itself; what was computed is still written and
!> the run ends with status 1.
module rs_app_run_scene
    use, intrinsic :: iso_fortran_env, only: error_unit, int64
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error, exit_not_reached
    use rs_core_interrupt, only: interrupt_signal, signal_name
    use rs_core_logger, only: log_info, log_debug, log_warning, logger_level, logger_set_level, &
        level_warning
    use rs_core_strings, only: str, str_significant
    use rs_core_timer, only: wall_time
    use rs_model_scene, only: scene_t, record_time
    use rs_parallel_mpi_env, only: world_rank, world_size, any_rank_true, mpi_library_version, &
        broadcast_array, max_each_over_ranks, sum_over_ranks, max_over_ranks, barrier, &
        broadcast_text, broadcast_flag
    use rs_io_result_file, only: result_meta_t, rod_layout_t, layout_of, pack_layout, &
        unpack_layout, result_writer_t, prepare_result_file, finish_result_file, read_checkpoint
    use rs_io_hdf5_file, only: hdf5_file_t
    use rs_io_scene_writer, only: resolved_scene_text
    use rs_io_scene_diff, only: first_scene_difference
    use rs_io_xdmf_writer, only: xdmf_rod_t, write_xdmf_sidecar
    use rs_solver_petsc_env, only: petsc_version
    use rs_solver_rod_stepper, only: petsc_apply_options, petsc_options_text
    use rs_solver_rod_run, only: rod_runner_t, step_count, system_plan_text
    use rs_model_coupling, only: coupled_systems, system_costs
    use rs_formulations_registry, only: is_bundle
    use rs_formulations_memory_estimate, only: memory_estimate_t, run_memory_estimate, &
        available_memory_bytes
    use rs_parallel_deal, only: deal_by_cost
    use rs_app_run_modes, only: run_modes, system_state_t
    implicit none
    private

    public :: run_scene, run_meta, collective_failure, coupled_system_plans

    !> The system of each rod, the rod's place among the system's rods, and each system's rods
    !> (members(first(k):first(k+1)-1)); set at the start of run_scene.
    integer, allocatable :: rod_system(:), rod_slot(:), system_first(:), system_members(:)
    !> The rank of each system: dealt by estimated cost (rs_parallel_deal).
    integer, allocatable :: system_rank(:)
    !> Systems solved by all ranks together (DESIGN.md §5: a bundle of ph_director rods coupled
    !> by joints, plates or contact, on PETSC_COMM_WORLD); rank 0 writes their records.
    logical, allocatable :: system_shared(:)

contains

    !> Run every rod of `scene` and write the result file; `err` is set (on every rank) if any
    !> rod failed or the file could not be written.
    subroutine run_scene(scene, command_line, err)
        type(scene_t), intent(in) :: scene
        character(len=*), intent(in) :: command_line
        type(error_t), allocatable, intent(out) :: err
        type(rod_runner_t), allocatable :: runners(:)
        type(rod_layout_t), allocatable :: layouts(:)
        type(system_state_t), allocatable :: states(:)
        type(result_writer_t) :: writer
        type(error_t), allocatable :: local_err
        character(len=:), allocatable :: path, message
        integer, allocatable :: records(:)
        real(rk), allocatable :: record_times(:), load_time(:)
        real(rk) :: started, output_seconds, last_report, t_flush, last_sidecar
        integer :: i, n, n_steps, first_step, capacity, n_times
        logical :: restarting, failed, last, unrelaxed
        integer :: flags(2), stop_signal

        call petsc_apply_options(scene_options(scene), trim(scene%solver%petsc_options), err)
        RS_RETURN_IF_ERROR(err)
        path = trim(scene%output%path)
        restarting = len_trim(scene%run%restart_from) > 0
        started = wall_time()
        output_seconds = 0.0_rk
        n_steps = step_count(scene)

        ! Build this rank's systems. Records between two flushes: the flush window at the
        ! stride, the initial record, an endpoint and a failure record.
        call coupled_systems(scene, rod_system, system_first, system_members)
        system_rank = deal_by_cost(system_costs(scene, system_first, system_members), world_size())
        call mark_shared(scene)
        if (allocated(rod_slot)) deallocate(rod_slot)
        allocate(rod_slot(size(scene%rods)))
        do i = 1, size(system_first) - 1
            rod_slot(system_members(system_first(i):system_first(i + 1) - 1)) = &
                [(n, n = 1, system_first(i + 1) - system_first(i))]
        end do
        capacity = scene%output%flush_every / scene%output%stride + 4
        allocate(runners(size(system_first) - 1))
        do i = 1, size(runners)
            if (.not. runs_here(i)) cycle
            call runners(i)%start(scene, system_members(system_first(i):system_first(i + 1) - 1), &
                capacity, restarting, local_err, shared=system_shared(i))
            if (allocated(local_err)) exit
        end do
        if (collective_failure(local_err, err, 'a rod could not be built (see above)')) return

        ! Every rank knows every rod's layout (the file's datasets are the same on all ranks).
        allocate(layouts(size(scene%rods)))
        call share_layouts(runners, layouts)

        ! A restart: each owner reads its rods' checkpoints before the file is touched.
        allocate(records(size(scene%rods)), source=0)
        first_step = 1
        if (restarting) then
            if (world_rank() == 0) call check_restart_scene(scene, local_err)
            if (collective_failure(local_err, err, 'the restart was refused (see rank 0)')) return
            call restore_checkpoints(scene, runners, records, first_step, local_err)
            if (collective_failure(local_err, err, 'the restart failed (see above)')) return
        end if

        ! Rank 0 creates the file (or carries the restart file over); then every rank opens it.
        ! Nothing computed can be lost to a path that cannot be written: this is before the
        ! time loop.
        if (world_rank() == 0) then
            if (restarting .and. trim(scene%run%restart_from) /= path) &
                call copy_file(trim(scene%run%restart_from), path, local_err)
            if (.not. allocated(local_err)) call prepare_result_file(path, run_meta(scene, &
                command_line), layouts, trim(scene%output%fields), local_err, restart=restarting)
        end if
        if (collective_failure(local_err, err, 'the result file could not be created (see ' // &
            'rank 0)')) return
        call writer%open(path, layouts, trim(scene%output%fields), records, world_size() > 1, &
            local_err)
        if (collective_failure(local_err, err, 'the result file could not be opened')) return
        if (restarting) call log_info('rodsolve: restarting from ' // &
            trim(scene%run%restart_from) // ' after step ' // str(first_step - 1) // ' (t = ' // &
            str(min(real(first_step - 1, rk) * scene%time%dt, scene%time%t_end)) // ')')

        ! The times of the records (the same for every rod that has not failed), for the sidecar.
        allocate(record_times(n_steps / scene%output%stride + 2))
        n_times = 0
        if (restarting) then
            if (world_rank() == 0) call read_record_times(trim(scene%run%restart_from), &
                layouts(1)%name, records(1), record_times, n_times, local_err)
            if (collective_failure(local_err, err, 'the restart file has no times (see rank 0)')) &
                return
        else
            n_times = 1
            record_times(1) = 0.0_rk
        end if

        ! The time loop: every rank steps its rods; the ranks meet only at the flushes.
        last_report = wall_time()
        last_sidecar = -huge(1.0_rk)
        stop_signal = 0
        do n = first_step, n_steps
            do i = 1, size(runners)
                if (runs_here(i)) call runners(i)%advance(scene, n)
            end do
            call log_debug('rodsolve: step ' // str(n) // ' done')
            ! The run ends when every system has failed, or with &time relaxation relaxed:
            ! nothing is left to step (and the step count and progress say so); or when a
            ! rank was asked to stop (SIGTERM, SIGINT): then everything is flushed and the
            ! file says 'interrupted'. One reduction for both.
            flags = [merge(1, 0, any(still_running())), interrupt_signal()]
            call max_each_over_ranks(flags)
            stop_signal = flags(2)
            last = n == n_steps .or. flags(1) == 0 .or. stop_signal /= 0
            if (mod(n, scene%output%stride) == 0 .or. last) then
                n_times = n_times + 1
                record_times(n_times) = record_time(scene, n)
            end if
            if (mod(n, scene%output%flush_every) == 0 .or. last) then
                t_flush = wall_time()
                call flush_records(scene, n, runners, writer, record_times(1:n_times), &
                    last_sidecar, err)
                output_seconds = output_seconds + (wall_time() - t_flush)
                ! Agreed on every rank by flush_records: all ranks stop here together.
                if (allocated(err)) then
                    call stop_after_write_failure(path, n, writer, err)
                    return
                end if
                call log_debug('rodsolve: flushed after step ' // str(n))
            end if
            if (wall_time() - last_report >= scene%run%progress_interval .or. last) then
                last_report = wall_time()
                call report_progress(scene, n, first_step, runners, last_report - started)
            end if
            if (last) exit
        end do
        unrelaxed = .false.
        if (scene%time%relaxation) then
            do i = 1, size(runners)
                if (system_owner(i) /= world_rank() .or. runners(i)%relaxed .or. runners(i)%failed) &
                    cycle
                unrelaxed = .true.
                call log_warning('rodsolve: ' // runners(i)%name() // ' did not relax by t_end = ' // &
                    str(scene%time%t_end) // ': kinetic energy ' // str_significant( &
                    runners(i)%kinetic_energy(), 3) // ' >= ' // &
                    str_significant(scene%time%kinetic_energy_tol, 3) // ' (raise t_end or the damping)')
            end do
        end if

        failed = any_rank_true(any(runners%failed))
        ! A relaxation that never relaxed is no static answer: its own status (issue 21 item 14).
        unrelaxed = any_rank_true(unrelaxed)
        call writer%close(local_err)
        t_flush = wall_time()
        if (world_rank() == 0 .and. .not. allocated(local_err)) then
            if (failed) then
                call finish_result_file(path, layouts, 'failed', local_err, trim(scene%run%units))
            else if (stop_signal /= 0 .and. n < n_steps) then
                call finish_result_file(path, layouts, 'interrupted', local_err, &
                    trim(scene%run%units))
            else if (unrelaxed) then
                call finish_result_file(path, layouts, 'not relaxed', local_err, &
                    trim(scene%run%units))
            else
                call finish_result_file(path, layouts, 'completed', local_err, &
                    trim(scene%run%units))
            end if
        end if
        output_seconds = output_seconds + (wall_time() - t_flush)
        if (collective_failure(local_err, err, 'the result file could not be completed')) return
        call report_summary(runners, started, output_seconds, min(n, n_steps) - first_step + 1, path)
        ! Modal analysis (&modes) about the reference state or the run's end state and its
        ! load time (every rank gets each system's from its owner), into the completed file.
        if (scene%modes%given .and. .not. failed) then
            allocate(states(size(runners)))
            if (trim(scene%modes%about) == 'equilibrium') then
                do i = 1, size(runners)
                    if (system_owner(i) == world_rank()) then
                        states(i)%x = runners(i)%x
                        load_time = [runners(i)%load_time()]
                    end if
                    call broadcast_array(states(i)%x, system_owner(i))
                    call broadcast_array(load_time, system_owner(i))
                    states(i)%load_time = load_time(1)
                end do
            end if
            call run_modes(scene, path, states, err)
            if (allocated(err)) return
        end if

        if (failed) then
            do i = 1, size(runners)
                if (.not. runners(i)%failed) cycle
                write(error_unit, '(a)') 'rodsolve: rod ''' // runners(i)%name() // &
                    ''' (rank ' // str(world_rank()) // '): ' // runners(i)%err%describe()
                flush(error_unit)
            end do
            call barrier()
            message = 'a rod failed (message above); what was computed is in ' // path
            ! On one rank (a sweep member runs alone) the message itself says why.
            if (world_size() == 1) then
                do i = 1, size(runners)
                    if (.not. runners(i)%failed) cycle
                    message = 'rod ''' // runners(i)%name() // ''' failed: ' // &
                        runners(i)%err%message // '; what was computed is in ' // path
                    exit
                end do
            end if
            RS_SET_ERROR(err, 'run_scene', message)
        else if (stop_signal /= 0 .and. n < n_steps) then
            if (trim(scene%time%continuation) == 'arc_length') then
                ! A path step has no time on the grid, and the path cannot be restarted.
                message = 'interrupted by ' // signal_name(stop_signal) // ' after path step ' // &
                    str(n) // ' of at most ' // str(n_steps) // ': every record up to it is ' // &
                    'in ' // path // ', with status ''interrupted'' (the load times in ' // &
                    '/rods/NAME/series/load_time); a continuation cannot be restarted: run it again'
            else
                message = 'interrupted by ' // signal_name(stop_signal) // ' after step ' // &
                    str(n) // ' of ' // str(n_steps) // ' (t = ' // str(real(n, rk) * &
                    scene%time%dt) // '): every record up to it and the checkpoint are in ' // &
                    path // ', with status ''interrupted''; &run restart_from = ''' // path // &
                    ''' with the same scene continues it'
            end if
            call set_error(err, message, 'run_scene', __FILE__, __LINE__, &
                exit_status=128 + stop_signal)
        else if (unrelaxed) then
            call set_error(err, 'the run did not relax by t_end = ' // str(scene%time%t_end) // &
                ' (above); its records are in ' // path // ', with status ''not relaxed''', &
                'run_scene', __FILE__, __LINE__, exit_status=exit_not_reached)
        end if
    contains

        !> Per system: on this rank, neither relaxed nor failed.
        function still_running() result(running)
            logical :: running(size(runners))
            integer :: k
            do k = 1, size(runners)
                running(k) = runs_here(k) .and. .not. runners(k)%relaxed .and. &
                    .not. runners(k)%failed
            end do
        end function still_running
    end subroutine run_scene

    !> Every rank gets every rod's layout from the rod's owner. A system's checkpoint (state and
    !> book-keeping) is stored with its first rod; its other rods have none.
    subroutine share_layouts(runners, layouts)
        type(rod_runner_t), intent(in), target :: runners(:)
        type(rod_layout_t), intent(inout) :: layouts(:)
        integer, allocatable :: header(:)
        real(rk), allocatable :: values(:)
        integer :: i
        do i = 1, size(layouts)
            if (rod_owner(i) == world_rank()) then
                associate (runner => runners(rod_system(i)))
                    if (rod_slot(i) == 1) then
                        layouts(i) = layout_of(runner%histories(1), size(runner%x), &
                            runner%system%n_ledger())
                    else
                        layouts(i) = layout_of(runner%histories(rod_slot(i)), 0, 0)
                        layouts(i)%checkpoint_rod = system_members(system_first(rod_system(i)))
                    end if
                end associate
                call pack_layout(layouts(i), header, values)
            end if
            call broadcast_array(header, rod_owner(i))
            call broadcast_array(values, rod_owner(i))
            if (rod_owner(i) /= world_rank()) call unpack_layout(header, values, layouts(i))
        end do
    end subroutine share_layouts

    !> A restart continues the scene its checkpoint was computed with: the restart file's
    !> /input/resolved and this scene's resolved text agree in every variable but those that
    !> do not change the motion (t_end, the output path and flushes, the sidecar, messages and
    !> the title). A changed dt made a checkpoint at t = 12 continue at t = 6.05; a changed
    !> stiffness continued silently (issue 21 item 7).
    subroutine check_restart_scene(scene, err)
        type(scene_t), intent(in) :: scene
        type(error_t), allocatable, intent(out) :: err
        character(len=*), parameter :: free(*) = [character(len=24) :: 'time%t_end', &
            'output%path', 'output%flush_every', 'output%xdmf', 'run%restart_from', &
            'run%progress_interval', 'run%log_level', 'run%title']
        type(hdf5_file_t) :: file
        type(error_t), allocatable :: close_err
        character(len=:), allocatable :: before, difference, message
        call file%open(trim(scene%run%restart_from), err, writable=.false.)
        if (allocated(err)) return
        call file%read_string_dataset('/input/resolved', before, err)
        call file%close(close_err)
        if (allocated(err)) return
        difference = first_scene_difference(before, resolved_scene_text(scene), free)
        if (len(difference) == 0) return
        message = 'restart_from = ''' // trim(scene%run%restart_from) // ''' continues another ' // &
            'scene: ' // difference // '. A restart continues the scene of its checkpoint ' // &
            '(only t_end, the output path and flushes, xdmf, progress_interval, log_level and ' // &
            'the title may change); run the changed scene from the start instead'
        RS_SET_ERROR(err, 'run_scene', message)
    end subroutine check_restart_scene

    !> Each owner restores its rods from the checkpoint of `restart_from`; every rank learns the
    !> records each rod has there and the first step to take (the same for all rods).
    subroutine restore_checkpoints(scene, runners, records, first_step, err)
        type(scene_t), intent(in) :: scene
        type(rod_runner_t), intent(inout) :: runners(:)
        integer, intent(inout) :: records(:)
        integer, intent(out) :: first_step
        type(error_t), allocatable, intent(out) :: err
        real(rk), allocatable :: state(:), ledger(:)
        integer :: i, step, steps(2)
        real(rk) :: time
        character(len=:), allocatable :: message
        steps = [-huge(1), -huge(1)]
        do i = 1, size(records)
            if (.not. runs_here(rod_system(i))) cycle
            if (rod_slot(i) > 1) then
                ! A system's state is in its first rod's checkpoint, read before (rod order);
                ! every rod of the system has as many records.
                records(i) = records(system_members(system_first(rod_system(i))))
                cycle
            end if
            call read_checkpoint(trim(scene%run%restart_from), trim(scene%rods(i)%name), state, &
                ledger, step, records(i), time, err)
            ! The run goes on at step * dt: a checkpoint at another time (a last step cut
            ! short at the old t_end) cannot be continued on this grid.
            if (.not. allocated(err) .and. abs(time - real(step, rk) * scene%time%dt) > &
                    1.0e-9_rk * max(abs(time), scene%time%dt)) then
                message = 'the checkpoint of "' // trim(scene%run%restart_from) // '" is at t = ' // &
                    str(time) // ', not on the step grid (step ' // str(step) // ' x dt = ' // &
                    str(real(step, rk) * scene%time%dt) // '): its last step was cut short at ' // &
                    't_end, so it cannot be continued; run it again with a t_end that is a ' // &
                    'multiple of dt'
                RS_SET_ERROR(err, 'run_scene', message)
            end if
            if (.not. allocated(err)) call runners(rod_system(i))%restore(scene, step, state, &
                ledger, err)
            if (allocated(err)) exit
            ! Largest and (negated) smallest step over this rank's rods.
            steps = max(steps, [step, -step])
        end do
        if (any_rank_true(allocated(err))) then
            first_step = 1
            if (.not. allocated(err)) then
                RS_SET_ERROR(err, 'run_scene', 'the restart failed on another rank (see above)')
            end if
            return
        end if
        call max_each_over_ranks(records)
        call max_each_over_ranks(steps)
        first_step = steps(1) + 1
        if (steps(1) /= -steps(2)) then
            message = 'the checkpoints of "' // trim(scene%run%restart_from) // '" are at ' // &
                'different steps (' // str(-steps(2)) // ' to ' // str(steps(1)) // '): a rod ' // &
                'failed before the last flush, so the run cannot be continued as a whole'
            RS_SET_ERROR(err, 'run_scene', message)
        else if (first_step > step_count(scene)) then
            message = 'the checkpoint of "' // trim(scene%run%restart_from) // '" is at the ' // &
                'last step already: nothing to continue (raise t_end to go further)'
            RS_SET_ERROR(err, 'run_scene', message)
        end if
    end subroutine restore_checkpoints

    !> Collective: the file makes room for every rod's new records, the ranks write them and
    !> the file is flushed; only when that succeeded on every rank are the checkpoints written
    !> and flushed, so a checkpoint never lists records that are not on disk. Then rank 0
    !> refreshes the XDMF sidecar (DESIGN.md §7). A failure on any rank (a full disk: issue 21
    !> item 3) is agreed on by all ranks, which return with the message of the first failing
    !> rank, after the records of this flush were cut off again (`drop_unflushed`): every
    !> record the file lists holds what was computed.
    subroutine flush_records(scene, n, runners, writer, record_times, last_sidecar, err)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: n
        type(rod_runner_t), intent(inout) :: runners(:)
        type(result_writer_t), intent(inout) :: writer
        real(rk), intent(in) :: record_times(:)
        !> Wall time of the last rewrite of the XDMF sidecar (rank 0).
        real(rk), intent(inout) :: last_sidecar
        type(error_t), allocatable, intent(out) :: err
        type(error_t), allocatable :: local_err, one_err, drop_err
        integer :: totals(size(rod_system)), failed(size(rod_system)), i
        real(rk) :: t
        real(rk), allocatable :: no_values(:)
        ! Every rank learns every rod's record count and whether it failed.
        totals = 0
        failed = 0
        do i = 1, size(totals)
            if (rod_owner(i) /= world_rank()) cycle
            totals(i) = writer%n_records(i) + runners(rod_system(i))%histories(rod_slot(i))%n_stored
            if (runners(rod_system(i))%failed) failed(i) = 1
        end do
        call max_each_over_ranks(totals)
        call max_each_over_ranks(failed)
        ! Disk space for the new records first: a full disk stops the run here, with the file
        ! whole (HDF5 does not recover from a failed flush: its file could not even be closed).
        if (world_rank() == 0) call writer%reserve(totals, local_err)
        if (shared_failure(local_err, err)) return
        ! Every call below is collective and made on every rank, whatever failed locally (the
        ! first local error is kept): ranks that skipped a call waited for each other forever.
        call writer%extend(totals, local_err)
        do i = 1, size(totals)
            if (rod_owner(i) == world_rank()) then
                associate (h => runners(rod_system(i))%histories(rod_slot(i)))
                    call writer%write_records(i, one_err, h)
                    call h%clear()
                end associate
            else
                call writer%write_records(i, one_err)
                ! The other ranks of a shared system keep the same records: drop them.
                if (system_shared(rod_system(i))) &
                    call runners(rod_system(i))%histories(rod_slot(i))%clear()
            end if
            call keep_first(one_err)
        end do
        call writer%flush(one_err)
        call keep_first(one_err)
        if (shared_failure(local_err, err)) then
            call writer%drop_unflushed(drop_err)
            if (any_rank_true(allocated(drop_err))) err%message = err%message // &
                '; cutting the file back to its last complete flush failed too, so its ' // &
                'last records may be damaged'
            return
        end if
        call writer%commit_records()
        ! The checkpoints of the records now on disk. A failed rod keeps the checkpoint of its
        ! last flush before the failure.
        t = min(real(n, rk) * scene%time%dt, scene%time%t_end)
        allocate(no_values(0))
        do i = 1, size(totals)
            if (failed(i) == 1) cycle
            if (rod_owner(i) == world_rank() .and. rod_slot(i) == 1) then
                ! A continuation's step n is a path step, off the time grid: its state is at
                ! its path's load time.
                associate (runner => runners(rod_system(i)))
                    call writer%write_checkpoint(i, n, merge(runner%load_time(), t, &
                        runner%continuation), one_err, runner%checkpoint_state(), runner%ledger())
                end associate
            else if (rod_owner(i) == world_rank()) then
                ! Coupled to the system's first rod, which holds the checkpoint.
                call writer%write_checkpoint(i, n, t, one_err, no_values, no_values)
            else
                call writer%write_checkpoint(i, n, t, one_err)
            end if
            call keep_first(one_err)
        end do
        call writer%flush(one_err)
        call keep_first(one_err)
        if (shared_failure(local_err, err)) return
        ! The sidecar grows with the records, so it is rewritten at most once per
        ! progress_interval, and at the last step. A failed rod has fewer records than the
        ! others: then it is not rewritten. Rank 0 writes it; its failure (a full disk) is
        ! agreed on like the others.
        if (world_rank() == 0 .and. scene%output%xdmf .and. (n >= step_count(scene) .or. &
                wall_time() - last_sidecar >= scene%run%progress_interval)) then
            if (all(totals == size(record_times))) then
                call write_sidecar(writer, record_times, local_err)
                last_sidecar = wall_time()
            end if
        end if
        if (shared_failure(local_err, err)) return
    contains
        subroutine keep_first(one)
            type(error_t), allocatable, intent(inout) :: one
            if (allocated(one) .and. .not. allocated(local_err)) call move_alloc(one, local_err)
            if (allocated(one)) deallocate(one)
        end subroutine keep_first
    end subroutine flush_records

    !> Collective: true on every rank if `local_err` is set on any; then `err` is set on every
    !> rank with the message of the first failing rank (rank 0 prints it: stop_all).
    logical function shared_failure(local_err, err)
        type(error_t), allocatable, intent(inout) :: local_err
        type(error_t), allocatable, intent(inout) :: err
        integer :: first(1)
        character(len=:), allocatable :: message
        first = -world_size()
        if (allocated(local_err)) first = -world_rank()
        call max_each_over_ranks(first)
        shared_failure = -first(1) < world_size()
        if (.not. shared_failure) return
        if (allocated(local_err)) message = local_err%message
        call broadcast_text(message, -first(1))
        if (allocated(local_err)) then
            call move_alloc(local_err, err)
        else
            call set_error(err, message // ' (on rank ' // str(-first(1)) // ')', 'run_scene', &
                __FILE__, __LINE__)
        end if
    end function shared_failure

    !> After a flush failed (agreed on every rank, `err` set): close the file, let rank 0 mark
    !> it 'failed' (without /series/, which a full disk could not take), and say in `err` what
    !> the file holds (issue 21 item 3).
    subroutine stop_after_write_failure(path, n, writer, err)
        character(len=*), intent(in) :: path
        integer, intent(in) :: n
        type(result_writer_t), intent(inout) :: writer
        type(error_t), allocatable, intent(inout) :: err
        type(error_t), allocatable :: close_err, status_err
        logical :: marked
        call writer%close(close_err)
        marked = .false.
        if (world_rank() == 0) then
            call finish_result_file(path, writer%layouts, 'failed', status_err, series=.false.)
            marked = .not. allocated(status_err)
        end if
        call broadcast_flag(marked, 0)
        err%message = 'the result file "' // path // '" could not be written after step ' // &
            str(n) // ': ' // err%message // '. The run stopped; '
        if (marked) then
            err%message = err%message // 'the file holds every record and the checkpoint ' // &
                'of the last complete flush, with status ''failed'''
        else
            err%message = err%message // 'the file''s status could not be written either ' // &
                '(it has none, like a killed run): its records and checkpoint are those of ' // &
                'the last complete flush'
        end if
    end subroutine stop_after_write_failure

    !> The times of the first `n` records of rod `name` in the result file `path` (a restart).
    subroutine read_record_times(path, name, n, times, n_times, err)
        character(len=*), intent(in) :: path, name
        integer, intent(in) :: n
        real(rk), intent(inout) :: times(:)
        integer, intent(out) :: n_times
        type(error_t), allocatable, intent(out) :: err
        type(hdf5_file_t) :: file
        type(error_t), allocatable :: close_err
        real(rk), allocatable :: values(:)
        n_times = 0
        call file%open(path, err, writable=.false.)
        if (allocated(err)) return
        call file%read('/rods/' // name // '/time', values, err)
        call file%close(close_err)
        if (allocated(err)) return
        n_times = min(n, size(values), size(times))
        times(1:n_times) = values(1:n_times)
    end subroutine read_record_times

    !> The XDMF sidecar for the records in the file (rank 0; DESIGN.md §7).
    subroutine write_sidecar(writer, times, err)
        type(result_writer_t), intent(in) :: writer
        real(rk), intent(in) :: times(:)
        type(error_t), allocatable, intent(out) :: err
        type(xdmf_rod_t) :: rods(size(writer%layouts))
        integer :: i, k
        logical :: has_position
        has_position = .true.
        do i = 1, size(writer%layouts)
            rods(i)%name = writer%layouts(i)%name
            rods(i)%n_nodes = writer%layouts(i)%n_nodes
            has_position = has_position .and. any(writer%fields(i)%list%path == 'position')
            do k = 1, size(writer%fields(i)%list)
                select case (trim(writer%fields(i)%list(k)%path))
                case ('velocity')
                    rods(i)%has_velocity = .true.
                case ('directors')
                    rods(i)%has_directors = .true.
                end select
            end do
        end do
        ! ParaView needs the centrelines; without them there is nothing to show.
        if (.not. has_position) return
        call write_xdmf_sidecar(writer%file%path, rods, times, err)
    end subroutine write_sidecar

    !> One progress line on rank 0 (its own rods): time, step, dt, Newton iterations,
    !> energy-balance error relative to the largest energy, estimated time left.
    subroutine report_progress(scene, n, first_step, runners, elapsed)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: n, first_step
        type(rod_runner_t), intent(in) :: runners(:)
        real(rk), intent(in) :: elapsed
        real(rk) :: balance, energy, left, load
        integer :: i, iterations
        if (world_rank() /= 0) return
        balance = 0.0_rk
        energy = 0.0_rk
        iterations = 0
        do i = 1, size(runners)
            if (system_owner(i) /= 0) cycle
            balance = max(balance, runners(i)%max_balance)
            energy = max(energy, runners(i)%max_energy)
            iterations = iterations + runners(i)%total_iterations
        end do
        left = elapsed / real(n - first_step + 1, rk) * real(step_count(scene) - n, rk)
        if (trim(scene%time%continuation) == 'arc_length') then
            ! A continuation: the path's step and the load time reached (largest over the
            ! systems); the steps left are at most path_steps - n.
            load = -huge(1.0_rk)
            do i = 1, size(runners)
                if (system_owner(i) == 0) load = max(load, runners(i)%path%load)
            end do
            call log_info('rodsolve: path step ' // str(n) // ' of at most ' // &
                str(step_count(scene)) // ', load time ' // str_significant(load, 6) // &
                ' (ends past ' // str(scene%time%t_end) // '), Newton iterations ' // &
                str(iterations) // ', ' // str_significant(elapsed, 3) // ' s')
            return
        end if
        call log_info('rodsolve: t = ' // str(min(real(n, rk) * scene%time%dt, &
            scene%time%t_end)) // ', step ' // str(n) // '/' // str(step_count(scene)) // &
            ', dt = ' // str(scene%time%dt) // ', Newton iterations ' // &
            str(iterations) // ', energy balance ' // str_significant(balance / max(energy, &
            tiny(1.0_rk)), 2) // ' of max H, ' // str_significant(elapsed, 3) // ' s, ' // &
            str_significant(left, 2) // ' s left')
    end subroutine report_progress

    !> The rods' summary lines and the run's: wall time, steps, rejected steps, Newton
    !> iterations, and where the time went (slowest rank).
    subroutine report_summary(runners, started, output_seconds, n_steps, path)
        type(rod_runner_t), intent(inout) :: runners(:)
        real(rk), intent(in) :: started, output_seconds
        integer, intent(in) :: n_steps
        character(len=*), intent(in) :: path
        real(rk) :: assembly, solve, output
        integer :: i, iterations, cutbacks
        assembly = 0.0_rk
        solve = 0.0_rk
        iterations = 0
        cutbacks = 0
        do i = 1, size(runners)
            if (.not. runs_here(i)) cycle
            assembly = assembly + runners(i)%assembly_seconds()
            solve = solve + runners(i)%solve_seconds - runners(i)%assembly_seconds()
            call runners(i)%finish(quiet=system_owner(i) /= world_rank())
            ! A shared system's counts once (its owner's).
            if (system_owner(i) /= world_rank()) cycle
            iterations = iterations + runners(i)%total_iterations
            cutbacks = cutbacks + runners(i)%total_cutbacks
        end do
        iterations = sum_over_ranks(iterations)
        cutbacks = sum_over_ranks(cutbacks)
        assembly = max_over_ranks(assembly)
        solve = max_over_ranks(solve)
        output = max_over_ranks(output_seconds)
        call log_info('rodsolve: ' // str(size(rod_system)) // ' rod(s), ' // str(n_steps) // &
            ' steps, ' // str(cutbacks) // ' rejected (cut-backs), ' // str(iterations) // &
            ' Newton iterations; wall time ' // str_significant(wall_time() - started, 3) // &
            ' s: assembly ' // str_significant(assembly, 3) // ' s, linear solves and Newton ' // &
            str_significant(solve, 3) // ' s, output ' // str_significant(output, 3) // &
            ' s (slowest rank); results in ' // path)
    end subroutine report_summary

    !> True (on every rank, with `err` set) if `local_err` is set on any rank: `err` is it
    !> there, and the message `elsewhere` on the other ranks.
    logical function collective_failure(local_err, err, elsewhere)
        type(error_t), allocatable, intent(inout) :: local_err
        type(error_t), allocatable, intent(inout) :: err
        character(len=*), intent(in) :: elsewhere
        collective_failure = any_rank_true(allocated(local_err))
        if (.not. collective_failure) return
        if (allocated(local_err)) then
            call move_alloc(local_err, err)
        else
            RS_SET_ERROR(err, 'run_scene', elsewhere)
        end if
    end function collective_failure

    function run_meta(scene, command_line) result(meta)
        type(scene_t), intent(in) :: scene
        character(len=*), intent(in) :: command_line
        type(result_meta_t) :: meta
        meta%command_line = command_line
        meta%n_ranks = world_size()
        meta%petsc_version = petsc_version()
        meta%mpi_version = mpi_library_version()
        meta%input_text = scene%source_text
        meta%input_resolved = resolved_scene_text(scene)
        meta%petsc_options = petsc_options_text()
        meta%title = trim(scene%run%title)
        meta%units = trim(scene%run%units)
    end function run_meta

    !> Copy the file `source` to `target` (a restart into a new result file).
    subroutine copy_file(source, target, err)
        character(len=*), intent(in) :: source, target
        type(error_t), allocatable, intent(out) :: err
        type(hdf5_file_t) :: probe
        character(len=:), allocatable :: message
        character(len=1), allocatable :: buffer(:)
        integer(int64) :: size_, at
        integer :: input, output, status, chunk
        ! Creating the target through the HDF5 layer makes its directories and checks them.
        call probe%create(target, err)
        if (allocated(err)) return
        call probe%close(err)
        if (allocated(err)) return
        open(newunit=input, file=source, access='stream', form='unformatted', status='old', &
            action='read', iostat=status)
        if (status /= 0) then
            message = 'cannot read the restart file "' // source // '"'
            RS_SET_ERROR(err, 'copy_file', message)
            return
        end if
        inquire(unit=input, size=size_)
        open(newunit=output, file=target, access='stream', form='unformatted', &
            status='replace', action='write', iostat=status)
        if (status /= 0) then
            close(input)
            message = 'cannot write "' // target // '"'
            RS_SET_ERROR(err, 'copy_file', message)
            return
        end if
        allocate(buffer(8 * 1024 * 1024))
        at = 0
        do while (at < size_)
            chunk = int(min(int(size(buffer), int64), size_ - at))
            read(input, iostat=status) buffer(1:chunk)
            if (status == 0) write(output, iostat=status) buffer(1:chunk)
            if (status /= 0) exit
            at = at + chunk
        end do
        close(input)
        close(output)
        if (status /= 0) then
            message = 'copying "' // source // '" to "' // target // '" failed'
            RS_SET_ERROR(err, 'copy_file', message)
        end if
    end subroutine copy_file

    !> Rank that runs system k: dealt by estimated cost at the start (longest first, to the
    !> least loaded rank), so independent rods spread evenly over the ranks.
    integer function system_owner(k)
        integer, intent(in) :: k
        system_owner = system_rank(k)
    end function system_owner

    !> True if this rank takes part in system k: it owns it, or the system is shared.
    logical function runs_here(k)
        integer, intent(in) :: k
        runs_here = system_owner(k) == world_rank() .or. system_shared(k)
    end function runs_here

    !> The shared systems: on more than one rank, a ph_director system that couples rods
    !> (joints, plates, contact) is solved by all ranks, and rank 0 owns its records.
    subroutine mark_shared(scene)
        type(scene_t), intent(in) :: scene
        integer :: k
        if (allocated(system_shared)) deallocate(system_shared)
        allocate(system_shared(size(system_first) - 1), source=.false.)
        if (world_size() == 1) return
        do k = 1, size(system_shared)
            system_shared(k) = is_bundle(scene, system_members(system_first(k):system_first(k + 1) - 1))
            if (system_shared(k)) system_rank(k) = 0
        end do
    end subroutine mark_shared

    !> The plans of the scene's coupled systems (rods joined by &joint or &plate, all rods with
    !> &contact, every rod with &obstacle) for --check-input: each built as a run builds it, with its linear solver
    !> and, on several ranks, its partition (rs_solver_rod_run%system_plan_text).
    function coupled_system_plans(scene, err) result(text)
        type(scene_t), intent(in) :: scene
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: text
        integer, allocatable :: system_of(:), first(:), members(:)
        integer :: k, level
        type(memory_estimate_t) :: memory
        text = ''
        call coupled_systems(scene, system_of, first, members)
        ! Built in full (not from 4 elements as the rods' lines): only what the run could build.
        memory = run_memory_estimate(scene, world_size())
        if (memory%known .and. memory%busiest_rank_bytes > available_memory_bytes()) then
            text = 'coupled systems: not built (the run would not fit in memory, see above)' // &
                new_line('a')
            return
        end if
        ! The plan is a namelist file with comments: what building the systems logs stays out.
        level = logger_level()
        call logger_set_level(level_warning)
        do k = 1, size(first) - 1
            if (.not. (is_bundle(scene, members(first(k):first(k + 1) - 1)) .or. &
                has_obstacles(scene))) cycle
            text = text // system_plan_text(scene, members(first(k):first(k + 1) - 1), &
                .true., err) // new_line('a')
            if (allocated(err)) exit
        end do
        call logger_set_level(level)
    end function coupled_system_plans

    pure logical function has_obstacles(scene)
        type(scene_t), intent(in) :: scene
        has_obstacles = .false.
        if (allocated(scene%obstacles)) has_obstacles = size(scene%obstacles) > 0
    end function has_obstacles

    !> Rank that runs rod i (the owner of its system).
    integer function rod_owner(i)
        integer, intent(in) :: i
        rod_owner = system_owner(rod_system(i))
    end function rod_owner

    !> PETSc options that follow from the scene (DESIGN.md §3): the Newton stopping rule of the
    !> method document with PETSc's relative tests off, and LU (the package is chosen per system
    !> by the stepper: MUMPS, or PETSc's LU where the formulation allows). `petsc_options` and the
    !> command line override them.
    function scene_options(scene) result(options)
        type(scene_t), intent(in) :: scene
        character(len=:), allocatable :: options
        options = '-snes_atol ' // str(scene%solver%newton_atol) // ' -snes_rtol ' // &
            str(scene%solver%newton_rtol) // ' -snes_stol 0 -snes_max_it ' // &
            str(scene%solver%max_newton) // ' -snes_max_funcs 1000000 -ksp_type preonly ' // &
            '-pc_type lu -mat_mumps_icntl_14 50'
    end function scene_options

end module rs_app_run_scene
