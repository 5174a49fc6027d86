#include "rs_macros.h"
!> Running a parameter sweep (DESIGN.md §5, §7; issue 9): the members of the scene's &sweep
!> groups (rs_io_sweep) are whole scenes, independent of each other. They are dealt to the
!> ranks by estimated cost (rs_parallel_deal: nodes x steps, the largest first) and each rank
!> runs its members one after the other, each as an ordinary scene on this process alone
!> (rs_parallel_mpi_env work_alone: sequential PETSc objects, no communication), writing an
!> ordinary result file under OUTPUT.h5.members/. A rank appends a line to its ledger after
!> every member, so a killed sweep keeps every finished member. At the end rank 0 merges the
!> members into the sweep's result file: /members/<id>/ (the member's /rods, /series and
!> /input, its parameter values as attributes) and /summary, one row per member. `rodsolve
!> --merge` does the same merge for a sweep that was killed.
!>
!> A failed member (Newton failure after all cut-backs, an invalid state) is recorded as failed
!> with its message; the others finish, and the run's error says how many failed.
module rs_app_run_sweep
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, error_list_t, set_error
    use rs_core_logger, only: log_info, log_warning, logger_level, logger_set_level, level_info, &
        level_warning
    use rs_core_strings, only: str, str_significant
    use rs_core_timer, only: wall_time
    use rs_core_interrupt, only: interrupt_signal, signal_name
    use rs_model_scene, only: scene_t
    use rs_model_coupling, only: coupled_systems, system_costs
    use rs_parallel_deal, only: deal_by_cost
    use rs_parallel_mpi_env, only: world_size, true_rank, barrier, work_alone, work_together, &
        any_rank_true, sum_over_ranks, max_over_ranks
    use rs_io_input_file, only: parse_scene
    use rs_io_input_check, only: check_capabilities
    use rs_io_sweep, only: sweep_member_t, sweep_member_count, sweep_member
    use rs_io_hdf5_file, only: hdf5_file_t
    use rs_io_scene_writer, only: resolved_scene_text
    use rs_io_scene_diff, only: first_scene_difference
    use rs_io_result_file, only: result_meta_t, prepare_sweep_file
    use rs_solver_rod_run, only: step_count
    use rs_app_run_scene, only: run_scene, run_meta, collective_failure
    implicit none
    private

    public :: run_sweep, merge_sweep

    !> Status codes of /summary/status.
    integer, parameter :: member_completed = 0, member_failed = 1, member_not_run = 2

    !> What the ledgers say of one member.
    type :: member_record_t
        integer :: status = member_not_run
        !> The rank that ran it (-1: none).
        integer :: rank = -1
        real(rk) :: wall_seconds = -1.0_rk
        character(len=:), allocatable :: message
    end type member_record_t

contains

    !> Run every member of the sweep `scene` (its text is scene%source_text) and write the
    !> sweep's result file; `err` (on every rank) if a member failed or the file could not be
    !> written.
    subroutine run_sweep(scene, command_line, err)
        type(scene_t), intent(in) :: scene
        character(len=*), intent(in) :: command_line
        type(error_t), allocatable, intent(out) :: err
        type(error_t), allocatable :: local_err, member_err
        type(sweep_member_t) :: member
        type(scene_t) :: member_scene
        real(rk), allocatable :: costs(:)
        integer, allocatable :: owner(:)
        real(rk) :: started, member_started
        integer :: n, id, ledger, mine, done, failed, ios, level, stop_signal
        character(len=:), allocatable :: path, message

        started = wall_time()
        n = sweep_member_count(scene)
        path = trim(scene%output%path)
        ! Every rank builds every member's scene to estimate its cost (the input check has
        ! parsed them all already, so they are valid): the same dealing everywhere.
        allocate(costs(n))
        do id = 1, n
            call build_member(scene, id, member, member_scene, local_err)
            if (allocated(local_err)) exit
            costs(id) = member_cost(member_scene)
        end do
        if (collective_failure(local_err, err, 'a sweep member could not be built (see rank 0)')) &
            return
        owner = deal_by_cost(costs, world_size())
        mine = count(owner == true_rank())
        call log_info('rodsolve: sweep of ' // str(n) // ' members on ' // str(world_size()) // &
            ' rank(s), dealt by estimated cost (slowest rank / mean = ' // &
            str_significant(balance(costs, owner), 4) // '); rank 0 runs ' // str(mine) // &
            '; members write to ' // member_directory(path) // '/')

        ! A new sweep replaces the previous one of this path from its start, so that a killed
        ! sweep never leaves the old result beside its own members (issue 21 item 5).
        if (true_rank() == 0) call forget_previous_sweep(path, world_size())
        ! This rank's ledger: one line per finished member, flushed, so a killed sweep keeps them.
        call open_ledger(path, true_rank(), ledger, local_err)
        done = 0
        failed = 0
        do id = 1, n
            if (allocated(local_err)) exit
            if (owner(id) /= true_rank()) cycle
            ! SIGTERM or SIGINT: no new member; the finished ones are merged below.
            if (interrupt_signal() /= 0) exit
            call build_member(scene, id, member, member_scene, local_err)
            if (allocated(local_err)) exit
            member_scene%output%path = member_file(path, id)
            member_scene%output%xdmf = .false.
            member_started = wall_time()
            ! A member's run prints its warnings, not its progress (one line per member below;
            ! &run log_level = 'debug' keeps everything).
            level = logger_level()
            if (level == level_info) call logger_set_level(level_warning)
            call work_alone()
            call run_scene(member_scene, command_line, member_err)
            call work_together()
            call logger_set_level(level)
            ! A member cut short by the signal is not run (no ledger line): --merge or a new
            ! sweep of it runs it whole.
            if (interrupt_signal() /= 0 .and. allocated(member_err)) exit
            done = done + 1
            if (allocated(member_err)) then
                failed = failed + 1
                message = one_line(member_err%describe())
                write(ledger, '(i0, 1x, a, 1x, es24.16e3, 1x, a)', iostat=ios) id, 'failed', &
                    wall_time() - member_started, message
                call log_warning('rodsolve: sweep member ' // str(id) // ' failed: ' // message)
                deallocate(member_err)
            else
                write(ledger, '(i0, 1x, a, 1x, es24.16e3)', iostat=ios) id, 'completed', &
                    wall_time() - member_started
            end if
            flush(ledger)
            call log_info('rodsolve: sweep member ' // str(id) // ' of ' // str(n) // ' done (' // &
                str(done) // ' of ' // str(mine) // ' on rank 0), ' // &
                str_significant(wall_time() - member_started, 3) // ' s')
        end do
        close(ledger, iostat=ios)
        failed = sum_over_ranks(failed)
        stop_signal = nint(max_over_ranks(real(interrupt_signal(), kind(1.0d0))))
        if (collective_failure(local_err, err, 'the sweep stopped on another rank (see there)')) &
            return
        call barrier()
        if (true_rank() == 0) call merge_sweep(scene, command_line, local_err, &
            seconds=wall_time() - started)
        if (collective_failure(local_err, err, 'the sweep''s result file could not be ' // &
            'written (see rank 0)')) return
        if (stop_signal /= 0) then
            message = 'the sweep was interrupted by ' // signal_name(stop_signal) // ': its ' // &
                'finished members are in ' // path // ' (the others have status ''not run''); ' // &
                'a sweep of the rest, or the whole scene again, completes it'
            call set_error(err, message, 'run_sweep', __FILE__, __LINE__, &
                exit_status=128 + stop_signal)
        else if (failed > 0) then
            message = str(failed) // ' of ' // str(n) // ' sweep members failed (their messages ' // &
                'are in ' // path // ': /summary/status and the message attribute of /members/<id>)'
            RS_SET_ERROR(err, 'run_sweep', message)
        end if
    end subroutine run_sweep


    !> Member `id` of the sweep `scene`: its text and values, and its scene parsed and checked.
    subroutine build_member(scene, id, member, member_scene, err)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: id
        type(sweep_member_t), intent(out) :: member
        type(scene_t), intent(out) :: member_scene
        type(error_t), allocatable, intent(out) :: err
        type(error_list_t) :: errors
        character(len=:), allocatable :: message
        call sweep_member(scene%source_text, scene%source_file, scene, id, member, errors)
        if (errors%count == 0) call parse_scene(member%text, scene%source_file, member_scene, errors)
        if (errors%count == 0) call check_capabilities(member_scene, errors)
        if (errors%count > 0) then
            message = 'sweep member ' // str(id) // ': ' // errors%joined()
            RS_SET_ERROR(err, 'run_sweep', message)
        end if
    end subroutine build_member

    !> Estimated cost of a member: its systems' nodes times its steps.
    real(rk) function member_cost(scene)
        type(scene_t), intent(in) :: scene
        integer, allocatable :: system_of(:), first(:), members(:)
        call coupled_systems(scene, system_of, first, members)
        member_cost = sum(system_costs(scene, first, members)) * real(step_count(scene), rk)
    end function member_cost

    !> The slowest rank's estimated cost over the mean.
    real(rk) function balance(costs, owner)
        real(rk), intent(in) :: costs(:)
        integer, intent(in) :: owner(:)
        real(rk), allocatable :: load(:)
        integer :: r
        allocate(load(0:world_size() - 1))
        do r = 0, world_size() - 1
            load(r) = sum(costs, mask=owner == r)
        end do
        balance = 1.0_rk
        if (sum(load) > 0.0_rk) balance = maxval(load) / (sum(load) / real(size(load), rk))
    end function balance

    ! ---- Files --------------------------------------------------------------------------------

    function member_directory(path) result(directory)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: directory
        directory = path // '.members'
    end function member_directory

    function member_file(path, id) result(file)
        character(len=*), intent(in) :: path
        integer, intent(in) :: id
        character(len=:), allocatable :: file
        file = member_directory(path) // '/member_' // str(id) // '.h5'
    end function member_file

    function ledger_file(path, rank) result(file)
        character(len=*), intent(in) :: path
        integer, intent(in) :: rank
        character(len=:), allocatable :: file
        file = member_directory(path) // '/ledger_rank' // str(rank) // '.txt'
    end function ledger_file

    !> Create (or empty) this rank's ledger, creating the members' directory.
    subroutine open_ledger(path, rank, unit, err)
        character(len=*), intent(in) :: path
        integer, intent(in) :: rank
        integer, intent(out) :: unit
        type(error_t), allocatable, intent(out) :: err
        type(hdf5_file_t) :: probe
        character(len=:), allocatable :: probe_path, message
        integer :: ios
        ! Creating a file through the HDF5 layer makes the directory (and checks it).
        probe_path = member_directory(path) // '/probe_rank' // str(rank) // '.h5'
        call probe%create(probe_path, err)
        if (allocated(err)) return
        call probe%close(err)
        if (allocated(err)) return
        call delete_file(probe_path)
        open(newunit=unit, file=ledger_file(path, rank), status='replace', action='write', &
            iostat=ios)
        if (ios /= 0) then
            message = 'cannot write the sweep ledger "' // ledger_file(path, rank) // '"'
            RS_SET_ERROR(err, 'run_sweep', message)
        end if
    end subroutine open_ledger

    !> Remove the result file of a previous sweep of `path` (rodsolve's own: the output guard
    !> checked it) and the ledgers of ranks from `n_ranks` on, which this sweep does not write
    !> and a merge would otherwise read as this sweep's.
    subroutine forget_previous_sweep(path, n_ranks)
        character(len=*), intent(in) :: path
        integer, intent(in) :: n_ranks
        integer :: rank
        logical :: exists
        call delete_file(path)
        rank = n_ranks
        do
            inquire(file=ledger_file(path, rank), exist=exists)
            if (.not. exists) exit
            call delete_file(ledger_file(path, rank))
            rank = rank + 1
        end do
    end subroutine forget_previous_sweep

    !> What the ledgers of ranks 0, 1, ... (until one is missing) say of members 1 .. n.
    subroutine read_ledgers(path, n, records)
        character(len=*), intent(in) :: path
        integer, intent(in) :: n
        type(member_record_t), intent(out) :: records(n)
        character(len=4096) :: line
        character(len=16) :: status
        integer :: rank, unit, ios, id, at
        real(rk) :: seconds
        logical :: exists
        rank = 0
        do
            inquire(file=ledger_file(path, rank), exist=exists)
            if (.not. exists) exit
            open(newunit=unit, file=ledger_file(path, rank), status='old', action='read', iostat=ios)
            do while (ios == 0)
                read(unit, '(a)', iostat=ios) line
                if (ios /= 0) exit
                read(line, *, iostat=ios) id, status, seconds
                if (ios /= 0 .or. id < 1 .or. id > n) then
                    ios = 0
                    cycle
                end if
                records(id)%wall_seconds = seconds
                records(id)%rank = rank
                records(id)%message = ''
                if (trim(status) == 'completed') then
                    records(id)%status = member_completed
                else
                    records(id)%status = member_failed
                    ! The message follows the third word.
                    at = index(line, trim(status)) + len_trim(status)
                    line = adjustl(line(at:))
                    at = index(line, ' ')
                    records(id)%message = trim(adjustl(line(at:)))
                end if
            end do
            close(unit)
            rank = rank + 1
        end do
        do id = 1, n
            if (.not. allocated(records(id)%message)) records(id)%message = 'not run'
        end do
    end subroutine read_ledgers

    !> Merge the finished members of the sweep `scene` into its result file (rank 0 only):
    !> /members/<id>/ and /summary; the members' files are removed once all are merged.
    subroutine merge_sweep(scene, command_line, err, seconds, verify)
        type(scene_t), intent(in) :: scene
        character(len=*), intent(in) :: command_line
        type(error_t), allocatable, intent(out) :: err
        real(rk), intent(in), optional :: seconds
        !> Check first that every member's file was computed from the member this scene builds
        !> (`rodsolve --merge`: the scene file may have been edited since the sweep ran).
        logical, intent(in), optional :: verify
        type(member_record_t), allocatable :: records(:)
        type(hdf5_file_t) :: file, source
        type(sweep_member_t) :: member
        type(error_list_t) :: errors
        type(result_meta_t) :: meta
        type(error_t), allocatable :: close_err
        character(len=:), allocatable :: path, group, first_rod, message
        real(rk), allocatable :: values(:, :), tip(:, :), final_time(:), max_balance(:), &
            iterations(:), wall(:)
        integer, allocatable :: status(:), ids(:), n_records(:), ranks(:)
        integer :: n, id, k
        logical :: exists

        n = sweep_member_count(scene)
        path = trim(scene%output%path)
        ! Without ledgers there is nothing to merge (the sweep never ran, or its file was
        ! written and the members' directory removed): never overwrite a result file then.
        inquire(file=ledger_file(path, 0), exist=exists)
        if (.not. exists) then
            message = 'nothing to merge: ' // member_directory(path) // '/ has no ledger of a ' // &
                'sweep (a finished sweep''s result file is complete already; run the scene to ' // &
                'start one)'
            RS_SET_ERROR(err, 'merge_sweep', message)
            return
        end if
        allocate(records(n))
        call read_ledgers(path, n, records)
        if (present(verify)) then
            if (verify) call verify_members(scene, records, err)
            if (allocated(err)) return
        end if
        meta = run_meta(scene, command_line)
        allocate(status(n), ids(n), n_records(n), final_time(n), max_balance(n), iterations(n), &
            wall(n), tip(3, n), ranks(n))
        ids = [(id, id = 1, n)]
        first_rod = '/rods/' // trim(scene%rods(1)%name)
        call prepare_sweep_file(path, meta, file, err)
        if (allocated(err)) return
        body: block
            do id = 1, n
                call sweep_member(scene%source_text, scene%source_file, scene, id, member, errors)
                if (errors%count > 0) then
                    message = errors%joined()
                    RS_SET_ERROR(err, 'merge_sweep', message)
                    exit body
                end if
                if (id == 1) allocate(values(size(member%values), n))
                values(:, id) = member%values
                status(id) = records(id)%status
                ranks(id) = records(id)%rank
                wall(id) = records(id)%wall_seconds
                final_time(id) = ieee_nan()
                max_balance(id) = ieee_nan()
                iterations(id) = ieee_nan()
                tip(:, id) = ieee_nan()
                n_records(id) = 0
                group = '/members/' // str(id)
                call file%create_group(group, err)
                if (allocated(err)) exit body
                do k = 1, size(member%parameters)
                    call file%write_attribute(group, trim(member%parameters(k)), member%values(k), err)
                    if (allocated(err)) exit body
                end do
                call file%write_attribute(group, 'status', trim(status_name(status(id))), err)
                if (.not. allocated(err)) call file%write_attribute(group, 'message', &
                    records(id)%message, err)
                if (.not. allocated(err)) call file%write_attribute(group, 'wall_time', wall(id), err)
                if (allocated(err)) exit body
                inquire(file=member_file(path, id), exist=exists)
                if (status(id) == member_not_run .or. .not. exists) cycle
                call source%open(member_file(path, id), err, writable=.false.)
                if (allocated(err)) exit body
                call file%copy_from(source, '/rods', group // '/rods', err)
                if (.not. allocated(err) .and. source%exists('/series')) &
                    call file%copy_from(source, '/series', group // '/series', err)
                if (.not. allocated(err)) call file%copy_from(source, '/input', group // '/input', err)
                ! The summary's quantities, of the member's first rod.
                if (.not. allocated(err)) call summary_of(source, first_rod, final_time(id), &
                    tip(:, id), max_balance(id), iterations(id), n_records(id), err)
                call source%close(close_err)
                if (allocated(err)) exit body
            end do
            call write_summary(file, first_rod, member%parameters, ids, values, status, wall, &
                final_time, tip, max_balance, iterations, n_records, ranks, err)
            if (allocated(err)) exit body
            call file%write_attribute('/', 'status', trim(sweep_status(status)), err)
            if (.not. allocated(err)) call file%write_attribute('/', 'members', n, err)
            if (.not. allocated(err) .and. present(seconds)) call file%write_attribute('/', &
                'wall_time', seconds, err)
        end block body
        call file%close(close_err)
        if (.not. allocated(err) .and. allocated(close_err)) call move_alloc(close_err, err)
        if (allocated(err)) return
        call log_info('rodsolve: sweep of ' // str(n) // ' members: ' // &
            str(count(status == member_completed)) // ' completed, ' // &
            str(count(status == member_failed)) // ' failed, ' // &
            str(count(status == member_not_run)) // ' not run; results in ' // path)
        ! Everything is in the sweep's file: the members' files and the ledgers go.
        do id = 1, n
            call delete_file(member_file(path, id))
        end do
        k = 0
        do
            inquire(file=ledger_file(path, k), exist=exists)
            if (.not. exists) exit
            call delete_file(ledger_file(path, k))
            k = k + 1
        end do
        call remove_directory(member_directory(path))
    end subroutine merge_sweep

    !> Before --merge writes anything: each finished member's file holds the resolved scene it
    !> ran (/input/resolved), which must be the member this scene builds now, apart from what
    !> does not change results (issue 21 item 8: an edited sweep scene relabelled members, a
    !> member computed at EI1 = 1.0 merged as 2.0).
    subroutine verify_members(scene, records, err)
        type(scene_t), intent(in) :: scene
        type(member_record_t), intent(in) :: records(:)
        type(error_t), allocatable, intent(out) :: err
        character(len=*), parameter :: free(*) = [character(len=24) :: 'output%flush_every', &
            'output%xdmf', 'run%progress_interval', 'run%log_level', 'run%title']
        type(sweep_member_t) :: member
        type(scene_t) :: member_scene
        type(hdf5_file_t) :: source
        type(error_t), allocatable :: close_err
        character(len=:), allocatable :: path, stored, difference, message
        integer :: id
        logical :: exists
        path = trim(scene%output%path)
        do id = 1, size(records)
            if (records(id)%status == member_not_run) cycle
            inquire(file=member_file(path, id), exist=exists)
            if (.not. exists) cycle
            call build_member(scene, id, member, member_scene, err)
            if (allocated(err)) return
            member_scene%output%path = member_file(path, id)
            member_scene%output%xdmf = .false.
            call source%open(member_file(path, id), err, writable=.false.)
            if (allocated(err)) return
            call source%read_string_dataset('/input/resolved', stored, err)
            call source%close(close_err)
            if (allocated(err)) return
            difference = first_scene_difference(stored, resolved_scene_text(member_scene), free, &
                'the member''s file')
            if (len(difference) == 0) cycle
            message = 'member ' // str(id) // ' was computed from another scene than the ' // &
                'one this scene builds now (' // difference // '): --merge needs the scene ' // &
                'file the sweep ran; nothing was merged'
            RS_SET_ERROR(err, 'merge_sweep', message)
            return
        end do
    end subroutine verify_members

    !> The summary quantities of one member, from rod `rod` (an HDF5 path /rods/<name>) of its
    !> result file: the last stored time, the last node's last position, the largest
    !> |energy-balance error| of a record, the Newton iterations (summed over the records) and
    !> the records.
    subroutine summary_of(source, rod, final_time, tip, max_balance, iterations, n_records, err)
        type(hdf5_file_t), intent(inout) :: source
        character(len=*), intent(in) :: rod
        real(rk), intent(inout) :: final_time, tip(3), max_balance, iterations
        integer, intent(out) :: n_records
        type(error_t), allocatable, intent(out) :: err
        real(rk), allocatable :: values(:)
        integer, allocatable :: counts(:)
        n_records = 0
        if (.not. source%exists(rod // '/time')) return
        call source%read(rod // '/time', values, err)
        if (allocated(err)) return
        n_records = size(values)
        if (n_records == 0) return
        final_time = values(size(values))
        if (source%exists(rod // '/position')) then
            call source%read(rod // '/position', values, err)
            if (allocated(err)) return
            tip = values(size(values) - 2:size(values))
        end if
        if (source%exists(rod // '/series/energy/balance_error')) then
            call source%read(rod // '/series/energy/balance_error', values, err)
            if (allocated(err)) return
            max_balance = maxval(abs(values))
        end if
        if (source%exists(rod // '/series/newton/iterations')) then
            call source%read(rod // '/series/newton/iterations', counts, err)
            if (allocated(err)) return
            iterations = real(sum(counts), rk)
        end if
    end subroutine summary_of

    !> /summary: one row per member, in id order.
    subroutine write_summary(file, rod_path, parameters, ids, values, status, wall, final_time, &
            tip, max_balance, iterations, n_records, ranks, err)
        type(hdf5_file_t), intent(inout) :: file
        character(len=*), intent(in) :: rod_path
        character(len=*), intent(in) :: parameters(:)
        integer, intent(in) :: ids(:), status(:), n_records(:), ranks(:)
        real(rk), intent(in) :: values(:, :), wall(:), final_time(:), tip(:, :), max_balance(:), &
            iterations(:)
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: rod
        real(rk), allocatable :: column(:)
        integer :: k
        rod = 'rod ''' // rod_path(7:) // ''''
        call file%write_dataset('/summary/id', ids, '-', 'member id: /members/<id>, [member]', err)
        if (allocated(err)) return
        do k = 1, size(parameters)
            column = values(k, :)
            call file%write_dataset('/summary/parameters/' // trim(parameters(k)), column, &
                '-', 'the member''s value of the swept variable ' // trim(parameters(k)) // &
                ' (its unit: docs/user/input.md), [member]', err)
            if (allocated(err)) return
        end do
        call file%write_dataset('/summary/status', status, '-', '0 completed, 1 failed (its ' // &
            'message: attribute message of /members/<id>), 2 not run (a killed sweep), [member]', err)
        if (.not. allocated(err)) call file%write_dataset('/summary/rank', ranks, '-', &
            'the rank that ran the member (-1: not run), [member]', err)
        if (.not. allocated(err)) call file%write_dataset('/summary/wall_time', wall, 's', &
            'wall time of the member''s run on its rank (-1: not run), [member]', err)
        if (.not. allocated(err)) call file%write_dataset('/summary/final_time', final_time, 's', &
            'time of the last record of ' // rod // ' (NaN: no result), [member]', err)
        if (.not. allocated(err)) call file%write_dataset('/summary/tip_position', tip, 'm', &
            'position of the last node of ' // rod // ' at its last record, [member x 3]', err)
        if (.not. allocated(err)) call file%write_dataset('/summary/max_balance_error', &
            max_balance, 'J', 'largest |energy-balance error| of a record of ' // rod // &
            ', [member]', err)
        if (.not. allocated(err)) call file%write_dataset('/summary/newton_iterations', &
            iterations, '-', 'Newton iterations (linear solves for se3_strand) of ' // rod // &
            ' over the run, [member]', err)
        if (.not. allocated(err)) call file%write_dataset('/summary/records', n_records, '-', &
            'records stored of ' // rod // ', [member]', err)
    end subroutine write_summary

    !> The sweep's status: 'completed', 'some members failed' (if any did) or 'incomplete: some
    !> members not run' (a killed sweep, merged).
    function sweep_status(status) result(text)
        integer, intent(in) :: status(:)
        character(len=:), allocatable :: text
        if (all(status == member_completed)) then
            text = 'completed'
        else if (any(status == member_failed)) then
            text = 'some members failed'
        else
            text = 'incomplete: some members not run'
        end if
    end function sweep_status

    function status_name(code) result(name)
        integer, intent(in) :: code
        character(len=9) :: name
        select case (code)
        case (member_completed)
            name = 'completed'
        case (member_failed)
            name = 'failed'
        case default
            name = 'not run'
        end select
    end function status_name

    !> A message on one line (a ledger line).
    function one_line(text) result(line)
        character(len=*), intent(in) :: text
        character(len=:), allocatable :: line
        integer :: i
        line = text
        do i = 1, len(line)
            if (line(i:i) == new_line('a') .or. line(i:i) == achar(13)) line(i:i) = ' '
        end do
    end function one_line

    function ieee_nan() result(x)
        use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
        real(rk) :: x
        x = ieee_value(1.0_rk, ieee_quiet_nan)
    end function ieee_nan

    !> Delete the file `path` if it exists.
    subroutine delete_file(path)
        character(len=*), intent(in) :: path
        integer :: unit, ios
        logical :: exists
        inquire(file=path, exist=exists)
        if (.not. exists) return
        open(newunit=unit, file=path, status='old', iostat=ios)
        if (ios == 0) close(unit, status='delete', iostat=ios)
    end subroutine delete_file

    !> Remove the (empty) directory `path`; a directory that is not empty stays.
    subroutine remove_directory(path)
        use, intrinsic :: iso_c_binding, only: c_char, c_int, c_null_char
        character(len=*), intent(in) :: path
        interface
            function c_rmdir(dir) bind(C, name='rmdir') result(status)
                import :: c_char, c_int
                character(kind=c_char), intent(in) :: dir(*)
                integer(c_int) :: status
            end function c_rmdir
        end interface
        integer(c_int) :: status
        status = c_rmdir(path // c_null_char)
    end subroutine remove_directory

end module rs_app_run_sweep
