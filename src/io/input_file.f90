!> Loading a scene file on every rank: rank 0 reads the text and broadcasts it (a missing or
!> unreadable file is reported like any other input error), then every rank reads, resolves
!> and checks the same text, so every rank holds the same scene and the same verdict without
!> further communication (DESIGN.md §6).
module rs_io_input_file
    use rs_core_error, only: error_list_t
    use rs_core_strings, only: text_buffer_t
    use rs_model_scene, only: scene_t
    use rs_parallel_mpi_env, only: world_rank, broadcast_text, broadcast_flag
    use rs_io_input_reader, only: read_scene_text
    use rs_io_input_check, only: resolve_scene, check_capabilities
    use rs_io_sweep, only: resolve_sweeps, check_sweep_members
    implicit none
    private

    public :: load_scene, parse_scene, read_text_file

contains

    !> Read, resolve and check scene `file`; problems (all of them) go to `errors`.
    subroutine load_scene(file, scene, errors)
        character(len=*), intent(in) :: file
        type(scene_t), intent(out) :: scene
        type(error_list_t), intent(inout) :: errors
        character(len=:), allocatable :: text, message
        logical :: ok
        if (world_rank() == 0) then
            call read_text_file(file, text, message)
            ok = len(message) == 0
            if (.not. ok) text = message
        end if
        call broadcast_flag(ok, 0)
        call broadcast_text(text, 0)
        if (.not. ok) then
            call errors%add(text)
            return
        end if
        call parse_scene(text, file, scene, errors)
        ! The language may describe more than this build can run (DESIGN.md §1); only a scene
        ! that reads cleanly is checked against the capability matrix.
        if (errors%count == 0) call check_capabilities(scene, errors)
        ! Every member of a sweep is a scene of its own and is checked as one (DESIGN.md §5);
        ! only a valid base scene, else each member would repeat its errors.
        if (errors%count == 0) call check_sweep_members(text, file, scene, errors)
    end subroutine load_scene

    !> Read, resolve and check scene text (no MPI): for unit tests and sweep members. The
    !> &sweep groups are checked (rs_io_sweep resolve_sweeps) but their members are not: that
    !> is load_scene's (check_sweep_members).
    subroutine parse_scene(text, file, scene, errors)
        character(len=*), intent(in) :: text, file
        type(scene_t), intent(out) :: scene
        type(error_list_t), intent(inout) :: errors
        integer :: before
        before = errors%count
        call read_scene_text(text, file, scene, errors)
        ! Cross-checks of values that could not be read would only repeat those errors.
        if (errors%count == before) then
            call resolve_scene(scene, errors)
            call resolve_sweeps(scene, errors)
        end if
    end subroutine parse_scene

    !> The whole contents of a text file; `message` is '' on success.
    subroutine read_text_file(file, text, message)
        character(len=*), intent(in) :: file
        character(len=:), allocatable, intent(out) :: text, message
        integer :: unit, ios, size_
        logical :: exists
        character(len=256) :: iomsg
        message = ''
        text = ''
        inquire(file=file, exist=exists, size=size_)
        if (.not. exists) then
            message = file // ': no such file'
            return
        end if
        ! A pipe or FIFO has no size (a scene written by another program, issue 21 item 19):
        ! it is read line by line to its end.
        if (size_ <= 0) then
            call read_lines(file, text, message)
            return
        end if
        call open_to_read(file, 'stream', unit, message)
        if (len(message) > 0) return
        deallocate(text)
        allocate(character(len=size_) :: text)
        read(unit, iostat=ios, iomsg=iomsg) text
        if (ios /= 0) message = file // ': cannot be read (' // trim(iomsg) // ')'
        close(unit)
    end subroutine read_text_file

    !> Open `file` for reading: 'stream' (its bytes) or 'sequential' (its lines); `message`
    !> is '' on success.
    subroutine open_to_read(file, access, unit, message)
        character(len=*), intent(in) :: file, access
        integer, intent(out) :: unit
        character(len=:), allocatable, intent(inout) :: message
        character(len=256) :: iomsg
        integer :: ios
        if (access == 'stream') then
            open(newunit=unit, file=file, access='stream', form='unformatted', action='read', &
                status='old', iostat=ios, iomsg=iomsg)
        else
            open(newunit=unit, file=file, access='sequential', form='formatted', action='read', &
                status='old', iostat=ios, iomsg=iomsg)
        end if
        if (ios /= 0) message = file // ': cannot be opened (' // trim(iomsg) // ')'
    end subroutine open_to_read

    !> The lines of `file` (any length), each ended by a new line, read to the end of the file.
    !> The text grows by doubling (appending each line to a copy of all before it was
    !> quadratic in the size of the scene, issue 21 item 17).
    subroutine read_lines(file, text, message)
        character(len=*), intent(in) :: file
        character(len=:), allocatable, intent(inout) :: text, message
        type(text_buffer_t) :: buffer
        character(len=4096) :: chunk
        character(len=256) :: iomsg
        integer :: unit, ios, got
        call open_to_read(file, 'sequential', unit, message)
        if (len(message) > 0) return
        do
            got = 0
            read(unit, '(a)', advance='no', size=got, iostat=ios, iomsg=iomsg) chunk
            ! A last line without its new line still counts.
            if (got > 0) call buffer%append(chunk(1:got))
            if (is_iostat_end(ios)) exit
            if (ios /= 0 .and. .not. is_iostat_eor(ios)) then
                message = file // ': cannot be read (' // trim(iomsg) // ')'
                exit
            end if
            if (is_iostat_eor(ios)) call buffer%append(new_line('a'))
        end do
        close(unit)
        text = buffer%text()
    end subroutine read_lines

end module rs_io_input_file
