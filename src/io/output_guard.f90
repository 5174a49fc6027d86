!> What a run may do to its output path (docs/user/output.md, "An existing file"): it holds
!> the path's lock for as long as it writes (two runs of one path: the second stops before it
!> touches anything; `--merge` of a sweep that is still running is refused), and it replaces
!> only a result of rodsolve: never the scene file itself, a directory, a file that is not
!> HDF5, or an HDF5 file rodsolve did not write. Rank 0 calls these; the run shares the outcome.
module rs_io_output_guard
    use, intrinsic :: iso_c_binding, only: c_char, c_int
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: to_c_string, from_c_string
    use rs_core_files, only: make_directories
    use rs_io_hdf5_file, only: hdf5_file_t
    implicit none
    private

    public :: output_lock_t, check_output_target, lock_path_of

    !> The lock of one output path, held from `acquire` to `release` (or the end of the
    !> process, when the kernel releases it).
    type :: output_lock_t
        integer(c_int) :: fd = -1
        character(len=:), allocatable :: lock_path
    contains
        procedure :: acquire => lock_acquire
        procedure :: release => lock_release
        procedure :: held => lock_held
    end type output_lock_t

    integer(c_int), parameter :: lock_taken = -1, lock_unsupported = -3
    integer(c_int), parameter :: kind_missing = 0, kind_directory = 1, kind_hdf5 = 2, &
        kind_other_file = 3

    interface
        function c_output_lock(lock_path, what, message, message_length) &
                bind(C, name='rs_output_lock') result(fd)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: lock_path(*), what(*)
            character(kind=c_char), intent(out) :: message(*)
            integer(c_int), value :: message_length
            integer(c_int) :: fd
        end function c_output_lock

        subroutine c_output_unlock(fd, lock_path) bind(C, name='rs_output_unlock')
            import :: c_char, c_int
            integer(c_int), value :: fd
            character(kind=c_char), intent(in) :: lock_path(*)
        end subroutine c_output_unlock

        function c_same_file(a, b) bind(C, name='rs_same_file') result(same)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: a(*), b(*)
            integer(c_int) :: same
        end function c_same_file

        function c_file_kind(path) bind(C, name='rs_file_kind') result(kind)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int) :: kind
        end function c_file_kind
    end interface

contains

    !> The lock file of output `path`.
    pure function lock_path_of(path) result(lock_path)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: lock_path
        lock_path = path // '.lock'
    end function lock_path_of

    !> Take the lock of output `path` for `what` (e.g. "a run of scene.nml"), written into the
    !> lock file with the process and host for the message another run gives. Fails if another
    !> process holds it. Where the file system has no locks, it warns through `warning` and
    !> goes on unprotected.
    subroutine lock_acquire(this, path, what, err, warning)
        class(output_lock_t), intent(inout) :: this
        character(len=*), intent(in) :: path, what
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable, intent(out) :: warning
        character(kind=c_char) :: message(1024)
        character(len=:), allocatable :: text
        integer(c_int) :: fd
        warning = ''
        if (index(path, '/', back=.true.) > 1) &
            call make_directories(path(1:index(path, '/', back=.true.) - 1))
        this%lock_path = lock_path_of(path)
        fd = c_output_lock(to_c_string(this%lock_path), to_c_string(what), message, &
            int(size(message), c_int))
        text = trim(from_c_string(message))
        if (len(text) > 0) then
            ! The lock file's text may end in a newline.
            if (text(len(text):len(text)) == new_line('a')) text = text(1:len(text) - 1)
        end if
        if (fd >= 0) then
            this%fd = fd
        else if (fd == lock_taken) then
            call set_error(err, 'the output "' // path // '" is being written by another run (' // &
                text // '; its lock is ' // this%lock_path // '): this run stops and leaves ' // &
                'it alone. Give this scene another &output path, or wait for that run', &
                'output_guard%acquire', __FILE__, __LINE__)
        else if (fd == lock_unsupported) then
            warning = 'the file system of "' // path // '" does not lock files (' // text // &
                '): a second run writing the same path at the same time would not be detected'
        else
            call set_error(err, 'cannot create the lock file ' // this%lock_path // ' of the ' // &
                'output (' // text // '): is the directory writable?', 'output_guard%acquire', &
                __FILE__, __LINE__)
        end if
    end subroutine lock_acquire

    !> Give the lock back and remove the lock file.
    subroutine lock_release(this)
        class(output_lock_t), intent(inout) :: this
        if (this%fd < 0) return
        call c_output_unlock(this%fd, to_c_string(this%lock_path))
        this%fd = -1
    end subroutine lock_release

    logical function lock_held(this)
        class(output_lock_t), intent(in) :: this
        lock_held = this%fd >= 0
    end function lock_held

    !> Whether a run may write its result to `path` (read from `scene_file`): nothing there,
    !> or a result of rodsolve (an HDF5 file with /input/text), which it replaces or, with
    !> `restart`, continues. Anything else is refused with a message that says what is there.
    subroutine check_output_target(path, scene_file, err)
        character(len=*), intent(in) :: path, scene_file
        type(error_t), allocatable, intent(out) :: err
        character(len=*), parameter :: routine = 'output_guard%check'
        type(hdf5_file_t) :: file
        type(error_t), allocatable :: open_err, close_err
        logical :: ours
        if (len(scene_file) > 0) then
            if (c_same_file(to_c_string(path), to_c_string(scene_file)) == 1) then
                call set_error(err, 'the output path "' // path // '" is the scene file ' // &
                    'itself: nothing was run (&output path names the result file)', routine, &
                    __FILE__, __LINE__)
                return
            end if
        end if
        select case (c_file_kind(to_c_string(path)))
        case (kind_missing)
            return
        case (kind_directory)
            call set_error(err, 'the output path "' // path // '" is a directory: give a ' // &
                'file name in &output path (e.g. "' // path // '/result.h5")', routine, &
                __FILE__, __LINE__)
        case (kind_hdf5)
            call file%open(path, open_err, writable=.false.)
            if (allocated(open_err)) then
                call set_error(err, '"' // path // '" exists and cannot be opened (is it open ' // &
                    'in another program?): rodsolve leaves it alone; give another &output ' // &
                    'path or close that program', routine, __FILE__, __LINE__)
                return
            end if
            ours = file%exists('/input/text')
            call file%close(close_err)
            if (.not. ours) call set_error(err, '"' // path // '" is an HDF5 file that ' // &
                'rodsolve did not write (no /input/text): rodsolve does not overwrite it; ' // &
                'give another &output path or remove it', routine, __FILE__, __LINE__)
        case (kind_other_file)
            call set_error(err, '"' // path // '" exists and is not an HDF5 file: rodsolve ' // &
                'does not overwrite it; give another &output path or remove it', routine, &
                __FILE__, __LINE__)
        case default
            call set_error(err, '"' // path // '" exists and is not a regular file (a pipe ' // &
                'or a device?): give a file name in &output path', routine, __FILE__, __LINE__)
        end select
    end subroutine check_output_target

end module rs_io_output_guard
