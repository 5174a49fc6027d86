!> A thin, checked layer over the HDF5 Fortran API (DESIGN.md §7; only src/io/ calls HDF5,
!> STYLE.md item 6). `create` and `open` use the default (serial) driver: one rank calls them.
!> `open(..., parallel=.true.)` opens a file on every rank with the MPI-IO driver, where every
!> call that changes metadata (set_records, attributes, flush, close) is collective (every rank,
!> same arguments, same order), and so are raw-data writes: a rank with nothing to write to a
!> dataset calls `write_no_records` on it.
!>
!> Every HDF5 call is checked; a failure returns an `error_t` naming the HDF5 call, the object,
!> the file and, when HDF5's error stack has it, the system's reason ("No space left on device
!> (errno 28)", hdf5_error_cause.c), and HDF5's own error-stack printing is switched off so that
!> the message is the only output.
!>
!> Conventions of the files written here:
!> - Fortran arrays are stored in Fortran order, so h5py and C see the dimensions reversed: a
!>   Fortran array (3, n_nodes, n_steps) is an h5py dataset of shape (n_steps, n_nodes, 3).
!> - Reals are IEEE double (little endian) and integers 32-bit signed in the file.
!> - Strings (attributes and text datasets) are variable-length UTF-8 scalars: h5py returns
!>   `str` for attributes and `bytes` for datasets (`ds.asstr()[()]` gives `str`). A string is
!>   cut at its first NUL character.
!> - A dataset whose last Fortran dimension counts stored steps (`series = .true.`) is chunked
!>   along that dimension (64 steps, fewer when one chunk would exceed 1 MiB; every other
!>   dimension whole), allocated early, with an unlimited maximum there, so it grows record by
!>   record (`set_records`, `write_records`); created with `checksum`, every chunk carries
!>   HDF5's Fletcher-32 checksum (files one rank writes: parallel HDF5 1.10 cannot write
!>   filtered datasets collectively). Other datasets are contiguous.
!> - `reserve` allocates disk space beyond the file's end before a file grows, so that a full
!>   disk is an error there and not in the middle of HDF5's writes.
module rs_io_hdf5_file
    use, intrinsic :: iso_c_binding, only: c_char, c_int, c_long_long, c_null_char, c_ptr, &
        c_null_ptr, c_loc, c_associated, c_f_pointer, c_size_t
    use rs_io_hdf5_info, only: hdf5_open_library
    use hdf5, only: hid_t, hsize_t, h5eset_auto_f, h5fcreate_f, h5fclose_f, h5ocopy_f, &
        h5gcreate_f, h5gclose_f, h5lexists_f, h5oopen_f, h5oclose_f, h5screate_f, &
        h5screate_simple_f, h5sclose_f, h5tcopy_f, h5tset_cset_f, h5tclose_f, h5aexists_f, &
        h5adelete_f, h5acreate_f, h5awrite_f, h5aclose_f, h5pcreate_f, h5pset_chunk_f, &
        h5pclose_f, h5dcreate_f, h5dwrite_f, h5dclose_f, H5F_ACC_TRUNC_F, H5S_SCALAR_F, &
        H5S_UNLIMITED_F, H5P_DATASET_CREATE_F, H5T_STRING, H5T_CSET_UTF8_F, H5T_NATIVE_DOUBLE, &
        H5T_NATIVE_INTEGER, H5T_IEEE_F64LE, H5T_STD_I32LE, h5fopen_f, h5fflush_f, &
        H5F_ACC_RDWR_F, H5F_ACC_RDONLY_F, H5F_SCOPE_GLOBAL_F, H5P_FILE_ACCESS_F, H5P_DEFAULT_F, &
        h5pset_fapl_mpio_f, h5dopen_f, h5dget_space_f, h5dset_extent_f, h5dread_f, &
        h5sget_simple_extent_ndims_f, h5sget_simple_extent_dims_f, h5sselect_hyperslab_f, &
        H5S_SELECT_SET_F, h5ldelete_f, h5pset_alloc_time_f, H5D_ALLOC_TIME_EARLY_F, &
        h5pset_fill_time_f, H5D_FILL_TIME_NEVER_F, h5pset_dxpl_mpio_f, H5FD_MPIO_COLLECTIVE_F, &
        H5P_DATASET_XFER_F, h5sselect_none_f, h5pset_fletcher32_f, h5dget_create_plist_f, &
        h5pget_nfilters_f
    use mpi, only: MPI_COMM_WORLD, MPI_INFO_NULL
    use, intrinsic :: iso_fortran_env, only: int64
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: str, to_c_string, from_c_string
    use rs_core_files, only: make_directories
    implicit none
    private

    public :: hdf5_file_t, series_chunk_records

    !> Most stored steps in one chunk of a series dataset.
    integer, parameter, public :: max_chunk_steps = 64
    !> Largest chunk of a series dataset in bytes (HDF5's default chunk cache is 1 MiB).
    integer, parameter :: max_chunk_bytes = 1024 * 1024

    integer(c_int), parameter :: access_exists = 0, access_write = 2

    !> A dataset kept open between calls (see hdf5_file_t%open_sets).
    type :: open_dataset_t
        character(len=:), allocatable :: path
        integer(hid_t) :: id = -1
    end type open_dataset_t

    !> One HDF5 file open for writing. Object paths are absolute ("/rods/arm/position") or
    !> relative to the root group; "/" is the root group.
    type :: hdf5_file_t
        !> HDF5 file identifier; negative while no file is open.
        integer(hid_t) :: id = -1
        !> The file name as given to `create`, for messages.
        character(len=:), allocatable :: path
        !> Opened on MPI_COMM_WORLD with the MPI-IO driver (`open(..., parallel=.true.)`).
        logical :: parallel = .false.
        !> The datasets that set_records, write_records, dataset_dims and read have opened,
        !> kept open until `delete` or `close`: H5Dopen walks the group's B-tree and copies
        !> property lists, and a writer flushing tens of datasets per record paid four opens
        !> and closes per dataset (most of a small sweep member's output time). Every rank of
        !> a parallel file makes the same calls, so every rank holds the same open datasets.
        type(open_dataset_t), allocatable :: open_sets(:)
        integer :: n_open = 0
        !> Where open_dataset last found a dataset (0-based), to start the next search there.
        integer :: last_found = 0
    contains
        !> Create (or truncate) a file, creating missing parent directories.
        procedure :: create => file_create
        !> Open an existing file for reading and writing (or reading only); `parallel` opens it
        !> on every rank of MPI_COMM_WORLD with the MPI-IO driver, where every call that
        !> changes metadata (set_records, flush, close, attributes) is collective and
        !> `write_records` is independent.
        procedure :: open => file_open
        !> Flush everything written to the disk (collective when parallel).
        procedure :: flush => file_flush
        !> Reserve disk space for `bytes` more of the file (one rank of a parallel file): fails
        !> with the system's reason (no space left, file too large) before anything is written.
        procedure :: reserve => file_reserve
        !> Whether an object (group or dataset) exists at `path`.
        procedure :: exists => file_exists
        !> Remove the link `path` (its storage is not reclaimed).
        procedure :: delete => file_delete
        !> Copy the object `object` (a group with everything below it, or a dataset) of another,
        !> open file to `target` in this one (H5Ocopy); the groups above `target` must exist.
        procedure :: copy_from => file_copy_from
        !> Dimensions of a dataset in Fortran order (the last one counts records in series).
        procedure :: dataset_dims => file_dataset_dims
        !> Create an empty series dataset (no records yet) of real or integer (`integer_values`)
        !> records of Fortran shape `record_dims`, with `unit` and `description`; `checksum`
        !> adds HDF5's Fletcher-32 checksum to every chunk (a file written by one rank only:
        !> parallel HDF5 1.10 cannot write filtered datasets).
        procedure :: create_series => file_create_series
        !> Whether a dataset has HDF5 filters (the Fletcher-32 checksum).
        procedure :: has_filters => file_has_filters
        !> Set the number of records (the last Fortran dimension) of a series dataset; grows or
        !> shrinks it. Collective when parallel.
        procedure :: set_records => file_set_records
        !> Write records first .. first + n - 1 of a series dataset from a flat array of n whole
        !> records (the dataset must hold them: see set_records). Collective when parallel.
        generic :: write_records => write_records_real, write_records_integer
        !> A rank's part of a collective `write_records` in a parallel file when it has nothing
        !> to write (does nothing in a serial file).
        procedure :: write_no_records => file_write_no_records
        !> Read a whole real or integer dataset into a flat array (Fortran element order).
        generic :: read => read_real, read_integer
        procedure, private :: write_records_real, write_records_integer, write_records_buffer, &
            write_selection
        procedure, private :: read_real, read_integer, read_buffer
        !> Close the file; does nothing when none is open.
        procedure :: close => file_close
        !> Whether a file is open.
        procedure :: is_open => file_is_open
        !> Create a group and any missing groups above it; an existing group is not an error.
        procedure :: create_group => file_create_group
        !> Write (or replace) an attribute of a group or dataset: a string, a default integer,
        !> a real scalar or a real vector.
        generic :: write_attribute => write_attribute_string, write_attribute_integer, &
            write_attribute_real, write_attribute_real_vector
        !> Write a scalar variable-length string dataset with `unit` and `description`.
        procedure :: write_string_dataset => file_write_string_dataset
        !> Read a scalar variable-length string dataset (as write_string_dataset writes).
        procedure :: read_string_dataset => file_read_string_dataset
        !> Write a real dataset of rank 1 to 4 or an integer dataset of rank 1 from a Fortran
        !> array, with `unit` and `description` attributes.
        generic :: write_dataset => write_real_1, write_real_2, write_real_3, write_real_4, &
            write_integer_1
        procedure, private :: write_attribute_string, write_attribute_integer, &
            write_attribute_real, write_attribute_real_vector
        procedure, private :: write_real_1, write_real_2, write_real_3, write_real_4, &
            write_integer_1
        procedure, private :: write_numeric_dataset, write_attribute_buffer, failed, &
            prepare_dataset, check_open, open_dataset, keep_dataset, close_datasets
    end type hdf5_file_t

    interface
        function c_access(path, mode) bind(C, name='access') result(status)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int), value :: mode
            integer(c_int) :: status
        end function c_access

        function c_reserve(file, path, bytes) bind(C, name='rs_hdf5_reserve') result(status)
            import :: c_char, c_int, hid_t, c_long_long
            integer(hid_t), value :: file
            character(kind=c_char), intent(in) :: path(*)
            integer(c_long_long), value :: bytes
            integer(c_int) :: status
        end function c_reserve

        subroutine c_error_text(number, text, size) bind(C, name='rs_error_text')
            import :: c_char, c_int
            integer(c_int), value :: number
            character(kind=c_char), intent(out) :: text(*)
            integer(c_int), value :: size
        end subroutine c_error_text

        !> The system's or MPI-IO's reason for the last failed HDF5 call (hdf5_error_cause.c).
        function c_hdf5_error_cause(text, size) bind(C, name='rs_hdf5_error_cause') &
                result(found)
            import :: c_char, c_int
            character(kind=c_char), intent(out) :: text(*)
            integer(c_int), value :: size
            integer(c_int) :: found
        end function c_hdf5_error_cause
    end interface

contains

    !> Create the file `path` for writing, replacing an existing file of that name. Missing
    !> parent directories are created (mode 0777 less the umask). Fails with a message naming
    !> the directory when it cannot be created or is not writable.
    subroutine file_create(this, path, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        type(error_t), allocatable, intent(out) :: err
        character(len=*), parameter :: routine = 'hdf5_file%create'
        character(len=:), allocatable :: directory
        integer :: status, slash

        if (this%is_open()) then
            call set_error(err, 'cannot create "' // path // '": this object still has "' // &
                this%path // '" open', routine, __FILE__, __LINE__)
            return
        end if
        this%path = path
        if (len_trim(path) == 0) then
            call set_error(err, 'cannot create an HDF5 file with an empty name', routine, &
                __FILE__, __LINE__)
            return
        end if
        slash = index(path, '/', back=.true.)
        if (slash == 0) then
            directory = '.'
        else if (slash == 1) then
            directory = '/'
        else
            directory = path(1:slash - 1)
        end if
        if (slash == len(path)) then
            call set_error(err, 'cannot create "' // path // '": the name is a directory', &
                routine, __FILE__, __LINE__)
            return
        end if
        call make_directories(directory)
        ! "dir/." resolves only when dir is a directory (a regular file gives ENOTDIR).
        if (c_access(to_c_string(directory // '/.'), access_exists) /= 0) then
            call set_error(err, 'cannot create the directory "' // directory // &
                '" for the output file "' // path // '"', routine, __FILE__, __LINE__)
            return
        end if
        if (c_access(to_c_string(directory), access_write) /= 0) then
            call set_error(err, 'cannot create "' // path // '": the directory "' // directory // &
                '" is not writable', routine, __FILE__, __LINE__)
            return
        end if

        call hdf5_open_library(status)
        if (this%failed(status, 'H5open', '/', routine, __LINE__, err)) return
        call h5eset_auto_f(0, status)
        if (this%failed(status, 'H5Eset_auto', '/', routine, __LINE__, err)) return
        call h5fcreate_f(path, H5F_ACC_TRUNC_F, this%id, status)
        if (status /= 0) then
            this%id = -1
            call set_error(err, 'cannot create the HDF5 file "' // path // &
                '" (H5Fcreate failed: is it open in another program, or the disk full?)', &
                routine, __FILE__, __LINE__)
        end if
    end subroutine file_create

    !> Close the file. Every object this module opens is closed before its procedure returns,
    !> except the datasets kept open (open_sets), which are closed first, so closing flushes
    !> everything written.
    subroutine file_close(this, err)
        class(hdf5_file_t), intent(inout) :: this
        type(error_t), allocatable, intent(out) :: err
        integer :: status, close_status
        if (.not. this%is_open()) return
        call this%close_datasets(close_status)
        call h5fclose_f(this%id, status)
        if (status == 0) status = close_status
        this%id = -1
        this%parallel = .false.
        if (this%failed(status, 'H5Fclose', '/', 'hdf5_file%close', __LINE__, err)) return
    end subroutine file_close

    logical function file_is_open(this)
        class(hdf5_file_t), intent(in) :: this
        file_is_open = this%id >= 0
    end function file_is_open

    !> Create the group `path` with the groups above it; existing groups are kept.
    subroutine file_create_group(this, path, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        type(error_t), allocatable, intent(out) :: err
        character(len=*), parameter :: routine = 'hdf5_file%create_group'
        integer(hid_t) :: group
        integer :: status, i
        logical :: exists
        call this%check_open(path, routine, err)
        if (allocated(err)) return
        do i = 2, len(path) + 1
            if (i <= len(path)) then
                if (path(i:i) /= '/') cycle
            end if
            if (path(i - 1:i - 1) == '/') cycle
            call h5lexists_f(this%id, path(1:i - 1), exists, status)
            if (this%failed(status, 'H5Lexists', path(1:i - 1), routine, __LINE__, err)) return
            if (exists) cycle
            call h5gcreate_f(this%id, path(1:i - 1), group, status)
            if (this%failed(status, 'H5Gcreate', path(1:i - 1), routine, __LINE__, err)) return
            call h5gclose_f(group, status)
            if (this%failed(status, 'H5Gclose', path(1:i - 1), routine, __LINE__, err)) return
        end do
    end subroutine file_create_group

    !> A string attribute `name` = `value` on the group or dataset `object`.
    subroutine write_attribute_string(this, object, name, value, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: object, name, value
        type(error_t), allocatable, intent(out) :: err
        character(kind=c_char), allocatable, target :: text(:)
        type(c_ptr), target :: pointer
        integer(hid_t) :: string_type
        integer :: status
        character(len=*), parameter :: routine = 'hdf5_file%write_attribute'
        call this%check_open(object, routine, err)
        if (allocated(err)) return
        call new_string_type(string_type, status)
        if (this%failed(status, 'H5Tcopy/H5Tset_cset', object // '@' // name, routine, &
                __LINE__, err)) return
        allocate(text, source=to_c_string(value))
        pointer = c_loc(text)
        call this%write_attribute_buffer(object, name, string_type, string_type, &
            [integer(hsize_t) ::], c_loc(pointer), err)
        call h5tclose_f(string_type, status)
        if (allocated(err)) return
        if (this%failed(status, 'H5Tclose', object // '@' // name, routine, __LINE__, err)) return
    end subroutine write_attribute_string

    !> An integer attribute (32-bit in the file) `name` = `value` on `object`.
    subroutine write_attribute_integer(this, object, name, value, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: object, name
        integer, intent(in), target :: value
        type(error_t), allocatable, intent(out) :: err
        call this%write_attribute_buffer(object, name, H5T_STD_I32LE, H5T_NATIVE_INTEGER, &
            [integer(hsize_t) ::], c_loc(value), err)
    end subroutine write_attribute_integer

    !> A real scalar attribute `name` = `value` on `object`.
    subroutine write_attribute_real(this, object, name, value, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: object, name
        real(rk), intent(in), target :: value
        type(error_t), allocatable, intent(out) :: err
        call this%write_attribute_buffer(object, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &
            [integer(hsize_t) ::], c_loc(value), err)
    end subroutine write_attribute_real

    !> A real vector attribute `name` = `values` on `object` (an empty vector is allowed).
    subroutine write_attribute_real_vector(this, object, name, values, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: object, name
        real(rk), intent(in), target, contiguous :: values(:)
        type(error_t), allocatable, intent(out) :: err
        real(rk), target :: dummy(1)
        if (size(values) == 0) then
            call this%write_attribute_buffer(object, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &
                [0_hsize_t], c_loc(dummy), err)
        else
            call this%write_attribute_buffer(object, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &
                [int(size(values), hsize_t)], c_loc(values), err)
        end if
    end subroutine write_attribute_real_vector

    !> A scalar variable-length UTF-8 string dataset `path` holding `text` (e.g. a whole input
    !> file), with a `description` and an empty `unit` (text has none).
    subroutine file_write_string_dataset(this, path, text, description, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path, text, description
        type(error_t), allocatable, intent(out) :: err
        character(len=*), parameter :: routine = 'hdf5_file%write_string_dataset'
        character(kind=c_char), allocatable, target :: buffer(:)
        type(c_ptr), target :: pointer
        integer(hid_t) :: string_type, space, dataset
        integer :: status, close_status

        call this%prepare_dataset(path, routine, err)
        if (allocated(err)) return
        string_type = -1
        space = -1
        dataset = -1
        body: block
            call new_string_type(string_type, status)
            if (this%failed(status, 'H5Tcopy/H5Tset_cset', path, routine, __LINE__, err)) &
                exit body
            call h5screate_f(H5S_SCALAR_F, space, status)
            if (this%failed(status, 'H5Screate', path, routine, __LINE__, err)) exit body
            call h5dcreate_f(this%id, path, string_type, space, dataset, status)
            if (this%failed(status, 'H5Dcreate', path, routine, __LINE__, err)) exit body
            allocate(buffer, source=to_c_string(text))
            pointer = c_loc(buffer)
            call h5dwrite_f(dataset, string_type, c_loc(pointer), status)
            if (this%failed(status, 'H5Dwrite', path, routine, __LINE__, err)) exit body
        end block body
        call close_all(dataset, space, string_type, close_status)
        if (allocated(err)) return
        if (this%failed(close_status, 'H5Dclose/H5Sclose/H5Tclose', path, routine, __LINE__, &
                err)) return
        call this%write_attribute(path, 'unit', '', err)
        if (allocated(err)) return
        call this%write_attribute(path, 'description', description, err)
    end subroutine file_write_string_dataset

    subroutine file_read_string_dataset(this, path, text, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        character(len=:), allocatable, intent(out) :: text
        type(error_t), allocatable, intent(out) :: err
        character(len=*), parameter :: routine = 'hdf5_file%read_string_dataset'
        type(c_ptr), target :: pointer
        type(c_ptr) :: buffer
        character(kind=c_char), pointer :: chars(:)
        integer(hid_t) :: string_type, dataset
        integer :: status, close_status, n
        interface
            pure function c_strlen(s) bind(C, name='strlen') result(n)
                import :: c_ptr, c_size_t
                type(c_ptr), value :: s
                integer(c_size_t) :: n
            end function c_strlen
            subroutine c_free(p) bind(C, name='free')
                import :: c_ptr
                type(c_ptr), value :: p
            end subroutine c_free
        end interface
        text = ''
        call this%check_open(path, routine, err)
        if (allocated(err)) return
        string_type = -1
        dataset = -1
        pointer = c_null_ptr
        body: block
            call new_string_type(string_type, status)
            if (this%failed(status, 'H5Tcopy/H5Tset_cset', path, routine, __LINE__, err)) &
                exit body
            call h5dopen_f(this%id, path, dataset, status)
            if (this%failed(status, 'H5Dopen', path, routine, __LINE__, err)) exit body
            buffer = c_loc(pointer)
            call h5dread_f(dataset, string_type, buffer, status)
            if (this%failed(status, 'H5Dread', path, routine, __LINE__, err)) exit body
            if (.not. c_associated(pointer)) exit body
            n = int(c_strlen(pointer))
            call c_f_pointer(pointer, chars, [n])
            text = from_c_string(chars)
            ! HDF5 allocated the string with the C library's malloc (default transfer).
            call c_free(pointer)
        end block body
        call close_all(dataset, -1_hid_t, string_type, close_status)
        if (allocated(err)) return
        if (this%failed(close_status, 'H5Dclose/H5Tclose', path, routine, __LINE__, err)) return
    end subroutine file_read_string_dataset

    !> A real rank-1 dataset (h5py shape (n,)). With `series`, the dimension counts steps.
    subroutine write_real_1(this, path, values, unit, description, err, series)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path, unit, description
        real(rk), intent(in), target, contiguous :: values(:)
        type(error_t), allocatable, intent(out) :: err
        logical, intent(in), optional :: series
        type(c_ptr) :: data
        data = c_null_ptr
        if (size(values) > 0) data = c_loc(values)
        call this%write_numeric_dataset(path, int(shape(values), hsize_t), H5T_IEEE_F64LE, &
            H5T_NATIVE_DOUBLE, storage_size(values) / 8, data, unit, description, &
            optional_true(series), err)
    end subroutine write_real_1

    !> A real rank-2 dataset; h5py shows the dimensions reversed. With `series`, the last
    !> Fortran dimension (h5py's first) counts steps.
    subroutine write_real_2(this, path, values, unit, description, err, series)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path, unit, description
        real(rk), intent(in), target, contiguous :: values(:, :)
        type(error_t), allocatable, intent(out) :: err
        logical, intent(in), optional :: series
        type(c_ptr) :: data
        data = c_null_ptr
        if (size(values) > 0) data = c_loc(values)
        call this%write_numeric_dataset(path, int(shape(values), hsize_t), H5T_IEEE_F64LE, &
            H5T_NATIVE_DOUBLE, storage_size(values) / 8, data, unit, description, &
            optional_true(series), err)
    end subroutine write_real_2

    !> A real rank-3 dataset; h5py shows the dimensions reversed. With `series`, the last
    !> Fortran dimension (h5py's first) counts steps.
    subroutine write_real_3(this, path, values, unit, description, err, series)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path, unit, description
        real(rk), intent(in), target, contiguous :: values(:, :, :)
        type(error_t), allocatable, intent(out) :: err
        logical, intent(in), optional :: series
        type(c_ptr) :: data
        data = c_null_ptr
        if (size(values) > 0) data = c_loc(values)
        call this%write_numeric_dataset(path, int(shape(values), hsize_t), H5T_IEEE_F64LE, &
            H5T_NATIVE_DOUBLE, storage_size(values) / 8, data, unit, description, &
            optional_true(series), err)
    end subroutine write_real_3

    !> A real rank-4 dataset; h5py shows the dimensions reversed. With `series`, the last
    !> Fortran dimension (h5py's first) counts steps.
    subroutine write_real_4(this, path, values, unit, description, err, series)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path, unit, description
        real(rk), intent(in), target, contiguous :: values(:, :, :, :)
        type(error_t), allocatable, intent(out) :: err
        logical, intent(in), optional :: series
        type(c_ptr) :: data
        data = c_null_ptr
        if (size(values) > 0) data = c_loc(values)
        call this%write_numeric_dataset(path, int(shape(values), hsize_t), H5T_IEEE_F64LE, &
            H5T_NATIVE_DOUBLE, storage_size(values) / 8, data, unit, description, &
            optional_true(series), err)
    end subroutine write_real_4

    !> A default-integer rank-1 dataset (32-bit in the file). With `series`, the dimension
    !> counts steps.
    subroutine write_integer_1(this, path, values, unit, description, err, series)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path, unit, description
        integer, intent(in), target, contiguous :: values(:)
        type(error_t), allocatable, intent(out) :: err
        logical, intent(in), optional :: series
        type(c_ptr) :: data
        data = c_null_ptr
        if (size(values) > 0) data = c_loc(values)
        call this%write_numeric_dataset(path, int(shape(values), hsize_t), H5T_STD_I32LE, &
            H5T_NATIVE_INTEGER, storage_size(values) / 8, data, unit, description, &
            optional_true(series), err)
    end subroutine write_integer_1

    !> Create the dataset `path` of Fortran shape `dims`, write `data` (not referenced when the
    !> dataset is empty) and its `unit` and `description`.
    subroutine write_numeric_dataset(this, path, dims, file_type, memory_type, element_bytes, &
            data, unit, description, series, err, checksum)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path, unit, description
        integer(hsize_t), intent(in) :: dims(:)
        integer(hid_t), intent(in) :: file_type, memory_type
        integer, intent(in) :: element_bytes
        type(c_ptr), intent(in) :: data
        logical, intent(in) :: series
        type(error_t), allocatable, intent(out) :: err
        !> A series with HDF5's Fletcher-32 checksum of every chunk (serial writers only).
        logical, intent(in), optional :: checksum
        character(len=*), parameter :: routine = 'hdf5_file%write_dataset'
        integer(hid_t) :: space, dataset, properties
        integer(hsize_t) :: max_dims(size(dims)), chunk(size(dims)), step_bytes
        integer :: status, close_status, rank

        call this%prepare_dataset(path, routine, err)
        if (allocated(err)) return
        rank = size(dims)
        space = -1
        dataset = -1
        properties = -1
        body: block
            call h5pcreate_f(H5P_DATASET_CREATE_F, properties, status)
            if (this%failed(status, 'H5Pcreate', path, routine, __LINE__, err)) exit body
            max_dims = dims
            if (series) then
                ! DESIGN.md §7: chunked and extendable along the steps.
                ! Records arrive a few at a time, so the chunk does not depend on how many
                ! there are now. Early allocation: the chunks exist once the extent is set, so
                ! ranks can write their records independently in a parallel file.
                max_dims(rank) = H5S_UNLIMITED_F
                chunk = max(dims, 1_hsize_t)
                step_bytes = product(chunk(1:rank - 1)) * int(element_bytes, hsize_t)
                chunk(rank) = int(series_chunk_records(step_bytes), hsize_t)
                call h5pset_chunk_f(properties, rank, chunk, status)
                if (this%failed(status, 'H5Pset_chunk', path, routine, __LINE__, err)) exit body
                call h5pset_alloc_time_f(properties, H5D_ALLOC_TIME_EARLY_F, status)
                if (this%failed(status, 'H5Pset_alloc_time', path, routine, __LINE__, err)) &
                    exit body
                ! No fill values: every record is written anyway.
                call h5pset_fill_time_f(properties, H5D_FILL_TIME_NEVER_F, status)
                if (this%failed(status, 'H5Pset_fill_time', path, routine, __LINE__, err)) &
                    exit body
                ! Damage on disk is then detected by every reader (issue 21 item 21).
                if (optional_true(checksum)) then
                    call h5pset_fletcher32_f(properties, status)
                    if (this%failed(status, 'H5Pset_fletcher32', path, routine, __LINE__, err)) &
                        exit body
                end if
            end if
            call h5screate_simple_f(rank, dims, space, status, max_dims)
            if (this%failed(status, 'H5Screate_simple', path, routine, __LINE__, err)) exit body
            call h5dcreate_f(this%id, path, file_type, space, dataset, status, &
                dcpl_id=properties)
            if (this%failed(status, 'H5Dcreate', path, routine, __LINE__, err)) exit body
            if (product(dims) > 0) then
                call h5dwrite_f(dataset, memory_type, data, status)
                if (this%failed(status, 'H5Dwrite', path, routine, __LINE__, err)) exit body
            end if
            ! On the new dataset's own handle: no lookup by path, no attribute to replace.
            call new_string_attribute(dataset, 'unit', unit, status)
            if (this%failed(status, 'H5Acreate/H5Awrite', path // '@unit', routine, __LINE__, &
                err)) exit body
            call new_string_attribute(dataset, 'description', description, status)
            if (this%failed(status, 'H5Acreate/H5Awrite', path // '@description', routine, &
                __LINE__, err)) exit body
            ! A series is written record by record: kept open for set_records and write_records.
            if (series) then
                call this%keep_dataset(path, dataset)
                dataset = -1
            end if
        end block body
        call close_all(dataset, space, -1_hid_t, close_status, properties)
        if (allocated(err)) return
        if (this%failed(close_status, 'H5Dclose/H5Sclose/H5Pclose', path, routine, __LINE__, &
                err)) return
    end subroutine write_numeric_dataset

    !> A new variable-length UTF-8 string attribute `name` = `value` of the open object
    !> `object` (which has no attribute of that name); status 0 on success.
    subroutine new_string_attribute(object, name, value, status)
        integer(hid_t), intent(in) :: object
        character(len=*), intent(in) :: name, value
        integer, intent(out) :: status
        character(kind=c_char), allocatable, target :: text(:)
        type(c_ptr), target :: pointer
        integer(hid_t) :: string_type, space, attribute
        integer :: close_status
        space = -1
        attribute = -1
        call new_string_type(string_type, status)
        if (status == 0) call h5screate_f(H5S_SCALAR_F, space, status)
        if (status == 0) call h5acreate_f(object, name, string_type, space, attribute, status)
        if (status == 0) then
            allocate(text, source=to_c_string(value))
            pointer = c_loc(text)
            call h5awrite_f(attribute, string_type, c_loc(pointer), status)
        end if
        if (attribute >= 0) then
            call h5aclose_f(attribute, close_status)
            if (status == 0) status = close_status
        end if
        call close_all(-1_hid_t, space, string_type, close_status)
        if (status == 0) status = close_status
    end subroutine new_string_attribute

    !> Create or replace attribute `name` of `object` with dataspace `dims` (scalar when empty)
    !> and write `data` of `memory_type`.
    subroutine write_attribute_buffer(this, object, name, file_type, memory_type, dims, data, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: object, name
        integer(hid_t), intent(in) :: file_type, memory_type
        integer(hsize_t), intent(in) :: dims(:)
        type(c_ptr), intent(in) :: data
        type(error_t), allocatable, intent(out) :: err
        character(len=*), parameter :: routine = 'hdf5_file%write_attribute'
        integer(hid_t) :: target_object, space, attribute
        integer :: status, close_status
        logical :: exists
        character(len=:), allocatable :: what

        call this%check_open(object, routine, err)
        if (allocated(err)) return
        what = 'attribute "' // name // '" of ' // object
        target_object = -1
        space = -1
        attribute = -1
        body: block
            call h5oopen_f(this%id, object, target_object, status)
            if (this%failed(status, 'H5Oopen', object, routine, __LINE__, err)) exit body
            call h5aexists_f(target_object, name, exists, status)
            if (this%failed(status, 'H5Aexists', what, routine, __LINE__, err)) exit body
            if (exists) then
                call h5adelete_f(target_object, name, status)
                if (this%failed(status, 'H5Adelete', what, routine, __LINE__, err)) exit body
            end if
            if (size(dims) == 0) then
                call h5screate_f(H5S_SCALAR_F, space, status)
            else
                call h5screate_simple_f(size(dims), dims, space, status)
            end if
            if (this%failed(status, 'H5Screate', what, routine, __LINE__, err)) exit body
            call h5acreate_f(target_object, name, file_type, space, attribute, status)
            if (this%failed(status, 'H5Acreate', what, routine, __LINE__, err)) exit body
            if (product(dims) > 0) then
                call h5awrite_f(attribute, memory_type, data, status)
                if (this%failed(status, 'H5Awrite', what, routine, __LINE__, err)) exit body
            end if
        end block body
        close_status = 0
        if (attribute >= 0) call h5aclose_f(attribute, status)
        if (attribute >= 0 .and. status /= 0) close_status = status
        if (space >= 0) call h5sclose_f(space, status)
        if (space >= 0 .and. status /= 0) close_status = status
        if (target_object >= 0) call h5oclose_f(target_object, status)
        if (target_object >= 0 .and. status /= 0) close_status = status
        if (allocated(err)) return
        if (this%failed(close_status, 'H5Aclose/H5Sclose/H5Oclose', what, routine, __LINE__, &
                err)) return
    end subroutine write_attribute_buffer

    !> Open the existing file `path`; `writable` (default true) for reading and writing.
    subroutine file_open(this, path, err, writable, parallel)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        type(error_t), allocatable, intent(out) :: err
        logical, intent(in), optional :: writable, parallel
        character(len=*), parameter :: routine = 'hdf5_file%open'
        integer(hid_t) :: access
        integer :: status, mode, close_status
        if (this%is_open()) then
            call set_error(err, 'cannot open "' // path // '": this object still has "' // &
                this%path // '" open', routine, __FILE__, __LINE__)
            return
        end if
        this%path = path
        this%parallel = optional_true(parallel)
        ! First: the Fortran API's constants (H5F_ACC_RDWR_F, ...) are set by H5open.
        call hdf5_open_library(status)
        if (this%failed(status, 'H5open', '/', routine, __LINE__, err)) return
        mode = H5F_ACC_RDWR_F
        if (present(writable)) then
            if (.not. writable) mode = H5F_ACC_RDONLY_F
        end if
        call h5eset_auto_f(0, status)
        if (this%failed(status, 'H5Eset_auto', '/', routine, __LINE__, err)) return
        access = H5P_DEFAULT_F
        if (this%parallel) then
            call h5pcreate_f(H5P_FILE_ACCESS_F, access, status)
            if (this%failed(status, 'H5Pcreate', '/', routine, __LINE__, err)) return
            call h5pset_fapl_mpio_f(access, MPI_COMM_WORLD, MPI_INFO_NULL, status)
            if (this%failed(status, 'H5Pset_fapl_mpio', '/', routine, __LINE__, err)) return
        end if
        call h5fopen_f(path, mode, this%id, status, access_prp=access)
        if (this%parallel) call h5pclose_f(access, close_status)
        if (status /= 0) then
            this%id = -1
            call set_error(err, 'cannot open the HDF5 file "' // path // &
                '" (H5Fopen failed: missing, not an HDF5 file, or locked by a running program?)', &
                routine, __FILE__, __LINE__)
        end if
    end subroutine file_open

    !> Records in one chunk of a series dataset whose records have `record_bytes` bytes.
    pure integer function series_chunk_records(record_bytes)
        integer(hsize_t), intent(in) :: record_bytes
        series_chunk_records = int(max(1_hsize_t, min(int(max_chunk_steps, hsize_t), &
            int(max_chunk_bytes, hsize_t) / max(record_bytes, 1_hsize_t))))
    end function series_chunk_records

    subroutine file_reserve(this, bytes, err)
        class(hdf5_file_t), intent(inout) :: this
        integer(int64), intent(in) :: bytes
        type(error_t), allocatable, intent(out) :: err
        integer(c_int) :: status
        character(kind=c_char) :: text(256)
        call this%check_open('/', 'hdf5_file%reserve', err)
        if (allocated(err)) return
        status = c_reserve(this%id, to_c_string(this%path), int(bytes, c_long_long))
        if (status == 0) return
        call c_error_text(status, text, size(text, kind=c_int))
        call set_error(err, 'no room for the next ' // str(int(min(bytes, int(huge(1), int64)))) &
            // ' bytes of "' // this%path // '": ' // from_c_string(text), 'hdf5_file%reserve', &
            __FILE__, __LINE__)
    end subroutine file_reserve

    subroutine file_flush(this, err)
        class(hdf5_file_t), intent(inout) :: this
        type(error_t), allocatable, intent(out) :: err
        integer :: status
        call this%check_open('/', 'hdf5_file%flush', err)
        if (allocated(err)) return
        call h5fflush_f(this%id, H5F_SCOPE_GLOBAL_F, status)
        if (this%failed(status, 'H5Fflush', '/', 'hdf5_file%flush', __LINE__, err)) return
    end subroutine file_flush

    !> True if every link along `path` exists (false also when no file is open).
    logical function file_exists(this, path)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        integer :: status, i
        logical :: exists
        file_exists = .false.
        if (.not. this%is_open()) return
        do i = 2, len(path) + 1
            if (i <= len(path)) then
                if (path(i:i) /= '/') cycle
            end if
            if (path(i - 1:i - 1) == '/') cycle
            call h5lexists_f(this%id, path(1:i - 1), exists, status)
            if (status /= 0 .or. .not. exists) return
        end do
        file_exists = .true.
    end function file_exists

    subroutine file_delete(this, path, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        type(error_t), allocatable, intent(out) :: err
        integer :: status
        call this%check_open(path, 'hdf5_file%delete', err)
        if (allocated(err)) return
        ! The link may be a kept dataset or a group above some: all of them are closed.
        call this%close_datasets(status)
        if (this%failed(status, 'H5Dclose', path, 'hdf5_file%delete', __LINE__, err)) return
        call h5ldelete_f(this%id, path, status)
        if (this%failed(status, 'H5Ldelete', path, 'hdf5_file%delete', __LINE__, err)) return
    end subroutine file_delete

    subroutine file_copy_from(this, source, object, target, err)
        class(hdf5_file_t), intent(inout) :: this
        type(hdf5_file_t), intent(in) :: source
        character(len=*), intent(in) :: object, target
        type(error_t), allocatable, intent(out) :: err
        integer :: status
        call this%check_open(target, 'hdf5_file%copy_from', err)
        if (allocated(err)) return
        if (.not. source%is_open()) then
            call set_error(err, 'cannot copy "' // object // '" to "' // target // &
                '": the source file is not open', 'hdf5_file%copy_from', __FILE__, __LINE__)
            return
        end if
        call h5ocopy_f(source%id, object, this%id, target, status)
        if (this%failed(status, 'H5Ocopy of ' // source%path // ':' // object, target, &
            'hdf5_file%copy_from', __LINE__, err)) return
    end subroutine file_copy_from

    subroutine file_dataset_dims(this, path, dims, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        integer, allocatable, intent(out) :: dims(:)
        type(error_t), allocatable, intent(out) :: err
        character(len=*), parameter :: routine = 'hdf5_file%dataset_dims'
        integer(hid_t) :: dataset, space
        integer(hsize_t) :: h5_dims(8), h5_max(8)
        integer :: status, rank, close_status
        call this%check_open(path, routine, err)
        if (allocated(err)) return
        space = -1
        body: block
            call this%open_dataset(path, dataset, status)
            if (this%failed(status, 'H5Dopen', path, routine, __LINE__, err)) exit body
            call h5dget_space_f(dataset, space, status)
            if (this%failed(status, 'H5Dget_space', path, routine, __LINE__, err)) exit body
            call h5sget_simple_extent_ndims_f(space, rank, status)
            if (this%failed(status, 'H5Sget_simple_extent_ndims', path, routine, __LINE__, err)) &
                exit body
            call h5sget_simple_extent_dims_f(space, h5_dims(1:rank), h5_max(1:rank), status)
            if (status < 0) then
                status = -1
                if (this%failed(status, 'H5Sget_simple_extent_dims', path, routine, __LINE__, &
                    err)) exit body
            end if
            ! HDF5's Fortran API returns the dimensions in Fortran order already.
            dims = int(h5_dims(1:rank))
        end block body
        call close_all(-1_hid_t, space, -1_hid_t, close_status)
        if (allocated(err)) return
        if (this%failed(close_status, 'H5Sclose', path, routine, __LINE__, err)) return
    end subroutine file_dataset_dims

    subroutine file_create_series(this, path, record_dims, integer_values, unit, description, &
            err, checksum)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path, unit, description
        integer, intent(in) :: record_dims(:)
        logical, intent(in) :: integer_values
        type(error_t), allocatable, intent(out) :: err
        logical, intent(in), optional :: checksum
        integer(hsize_t) :: dims(size(record_dims) + 1)
        dims(1:size(record_dims)) = int(record_dims, hsize_t)
        dims(size(dims)) = 0
        if (integer_values) then
            call this%write_numeric_dataset(path, dims, H5T_STD_I32LE, H5T_NATIVE_INTEGER, 4, &
                c_null_ptr, unit, description, .true., err, optional_true(checksum))
        else
            call this%write_numeric_dataset(path, dims, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 8, &
                c_null_ptr, unit, description, .true., err, optional_true(checksum))
        end if
    end subroutine file_create_series

    !> Whether the dataset `path` has HDF5 filters (a Fletcher-32 checksum): parallel HDF5 1.10
    !> cannot write such a dataset collectively.
    logical function file_has_filters(this, path, err) result(filtered)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        type(error_t), allocatable, intent(out) :: err
        character(len=*), parameter :: routine = 'hdf5_file%has_filters'
        integer(hid_t) :: dataset, properties
        integer :: status, n_filters, close_status
        filtered = .false.
        call this%open_dataset(path, dataset, status)
        if (this%failed(status, 'H5Dopen', path, routine, __LINE__, err)) return
        call h5dget_create_plist_f(dataset, properties, status)
        if (this%failed(status, 'H5Dget_create_plist', path, routine, __LINE__, err)) return
        call h5pget_nfilters_f(properties, n_filters, status)
        call h5pclose_f(properties, close_status)
        if (this%failed(status, 'H5Pget_nfilters', path, routine, __LINE__, err)) return
        if (this%failed(close_status, 'H5Pclose', path, routine, __LINE__, err)) return
        filtered = n_filters > 0
    end function file_has_filters

    subroutine file_set_records(this, path, n_records, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        integer, intent(in) :: n_records
        type(error_t), allocatable, intent(out) :: err
        character(len=*), parameter :: routine = 'hdf5_file%set_records'
        integer, allocatable :: dims(:)
        integer(hid_t) :: dataset
        integer :: status
        call this%dataset_dims(path, dims, err)
        if (allocated(err)) return
        ! Called even for the same extent: collective in a parallel file.
        dims(size(dims)) = n_records
        call this%open_dataset(path, dataset, status)
        if (this%failed(status, 'H5Dopen', path, routine, __LINE__, err)) return
        call h5dset_extent_f(dataset, int(dims, hsize_t), status)
        if (this%failed(status, 'H5Dset_extent', path, routine, __LINE__, err)) return
    end subroutine file_set_records

    subroutine write_records_real(this, path, first, values, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        integer, intent(in) :: first
        real(rk), intent(in), target, contiguous :: values(:)
        type(error_t), allocatable, intent(out) :: err
        if (size(values) == 0) return
        call this%write_records_buffer(path, first, size(values), H5T_NATIVE_DOUBLE, &
            c_loc(values), err)
    end subroutine write_records_real

    subroutine write_records_integer(this, path, first, values, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        integer, intent(in) :: first
        integer, intent(in), target, contiguous :: values(:)
        type(error_t), allocatable, intent(out) :: err
        if (size(values) == 0) return
        call this%write_records_buffer(path, first, size(values), H5T_NATIVE_INTEGER, &
            c_loc(values), err)
    end subroutine write_records_integer

    !> Write `count` values (whole records) into the series dataset `path` from record `first`.
    subroutine write_records_buffer(this, path, first, count, memory_type, data, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        integer, intent(in) :: first, count
        integer(hid_t), intent(in) :: memory_type
        type(c_ptr), intent(in) :: data
        type(error_t), allocatable, intent(out) :: err
        character(len=*), parameter :: routine = 'hdf5_file%write_records'
        integer, allocatable :: dims(:)
        integer(hsize_t), allocatable :: start(:), block_dims(:)
        integer :: rank, per_record, n
        call this%dataset_dims(path, dims, err)
        if (allocated(err)) return
        rank = size(dims)
        per_record = max(1, product(dims(1:rank - 1)))
        n = count / per_record
        if (n * per_record /= count .or. first < 1 .or. first + n - 1 > dims(rank)) then
            ! The other ranks are in the collective write: take part with nothing.
            call this%write_no_records(path, err)
            if (allocated(err)) deallocate(err)
            call set_error(err, 'cannot write ' // str(count) // ' values as records ' // &
                str(first) // '.. of "' // path // '" in "' // this%path // &
                '": not whole records, or beyond its ' // str(dims(rank)) // ' records', &
                routine, __FILE__, __LINE__)
            return
        end if
        allocate(start(rank), source=0_hsize_t)
        start(rank) = int(first - 1, hsize_t)
        block_dims = int(dims, hsize_t)
        block_dims(rank) = int(n, hsize_t)
        call this%write_selection(path, memory_type, data, err, start, block_dims)
    end subroutine write_records_buffer

    subroutine file_write_no_records(this, path, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        type(error_t), allocatable, intent(out) :: err
        real(rk), target :: dummy(1)
        if (.not. this%parallel) return
        call this%write_selection(path, H5T_NATIVE_DOUBLE, c_loc(dummy), err)
    end subroutine file_write_no_records

    !> Write `data` into the block of dataset `path` at `start` with dimensions `block_dims`,
    !> or (both absent) nothing: this rank's part of a collective write.
    subroutine write_selection(this, path, memory_type, data, err, start, block_dims)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        integer(hid_t), intent(in) :: memory_type
        type(c_ptr), intent(in) :: data
        type(error_t), allocatable, intent(out) :: err
        integer(hsize_t), intent(in), optional :: start(:), block_dims(:)
        character(len=*), parameter :: routine = 'hdf5_file%write_records'
        integer(hid_t) :: dataset, file_space, memory_space, transfer
        integer :: status, close_status
        file_space = -1
        memory_space = -1
        transfer = H5P_DEFAULT_F
        body: block
            call this%open_dataset(path, dataset, status)
            if (this%failed(status, 'H5Dopen', path, routine, __LINE__, err)) exit body
            call h5dget_space_f(dataset, file_space, status)
            if (this%failed(status, 'H5Dget_space', path, routine, __LINE__, err)) exit body
            if (present(block_dims)) then
                call h5sselect_hyperslab_f(file_space, H5S_SELECT_SET_F, start, block_dims, status)
                if (this%failed(status, 'H5Sselect_hyperslab', path, routine, __LINE__, err)) &
                    exit body
                call h5screate_simple_f(size(block_dims), block_dims, memory_space, status)
                if (this%failed(status, 'H5Screate_simple', path, routine, __LINE__, err)) &
                    exit body
            else
                call h5sselect_none_f(file_space, status)
                if (this%failed(status, 'H5Sselect_none', path, routine, __LINE__, err)) exit body
                call h5screate_simple_f(1, [1_hsize_t], memory_space, status)
                if (this%failed(status, 'H5Screate_simple', path, routine, __LINE__, err)) &
                    exit body
                call h5sselect_none_f(memory_space, status)
                if (this%failed(status, 'H5Sselect_none', path, routine, __LINE__, err)) exit body
            end if
            call transfer_properties(this%parallel, transfer, status)
            if (this%failed(status, 'H5Pset_dxpl_mpio', path, routine, __LINE__, err)) exit body
            call h5dwrite_f(dataset, memory_type, data, status, mem_space_id=memory_space, &
                file_space_id=file_space, xfer_prp=transfer)
            if (this%failed(status, 'H5Dwrite', path, routine, __LINE__, err)) exit body
        end block body
        call close_all(-1_hid_t, file_space, -1_hid_t, close_status)
        if (memory_space >= 0) call h5sclose_f(memory_space, status)
        if (transfer /= H5P_DEFAULT_F) call h5pclose_f(transfer, status)
        if (allocated(err)) return
        if (this%failed(close_status, 'H5Sclose', path, routine, __LINE__, err)) return
    end subroutine write_selection

    !> Raw-data transfer properties: collective MPI-IO in a parallel file (every rank writes
    !> every dataset, possibly nothing), the default otherwise.
    subroutine transfer_properties(parallel, transfer, status)
        logical, intent(in) :: parallel
        integer(hid_t), intent(out) :: transfer
        integer, intent(out) :: status
        transfer = H5P_DEFAULT_F
        status = 0
        if (.not. parallel) return
        call h5pcreate_f(H5P_DATASET_XFER_F, transfer, status)
        if (status /= 0) return
        call h5pset_dxpl_mpio_f(transfer, H5FD_MPIO_COLLECTIVE_F, status)
    end subroutine transfer_properties

    subroutine read_real(this, path, values, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        real(rk), allocatable, target, intent(out) :: values(:)
        type(error_t), allocatable, intent(out) :: err
        integer, allocatable :: dims(:)
        call this%dataset_dims(path, dims, err)
        if (allocated(err)) return
        allocate(values(product(dims)))
        if (size(values) == 0) return
        call this%read_buffer(path, H5T_NATIVE_DOUBLE, c_loc(values), err)
    end subroutine read_real

    subroutine read_integer(this, path, values, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        integer, allocatable, target, intent(out) :: values(:)
        type(error_t), allocatable, intent(out) :: err
        integer, allocatable :: dims(:)
        call this%dataset_dims(path, dims, err)
        if (allocated(err)) return
        allocate(values(product(dims)))
        if (size(values) == 0) return
        call this%read_buffer(path, H5T_NATIVE_INTEGER, c_loc(values), err)
    end subroutine read_integer

    subroutine read_buffer(this, path, memory_type, data, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        integer(hid_t), intent(in) :: memory_type
        type(c_ptr), intent(in) :: data
        type(error_t), allocatable, intent(out) :: err
        integer(hid_t) :: dataset
        integer :: status
        type(c_ptr) :: buffer
        buffer = data
        call this%open_dataset(path, dataset, status)
        if (this%failed(status, 'H5Dopen', path, 'hdf5_file%read', __LINE__, err)) return
        call h5dread_f(dataset, memory_type, buffer, status)
        if (this%failed(status, 'H5Dread', path, 'hdf5_file%read', __LINE__, err)) return
    end subroutine read_buffer

    !> The dataset `path`, opened on its first use and kept open until `delete` or `close`
    !> (status as H5Dopen's).
    subroutine open_dataset(this, path, dataset, status)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        integer(hid_t), intent(out) :: dataset
        integer, intent(out) :: status
        integer :: k, i
        status = 0
        ! A writer visits its datasets in the same order at every flush (dims, extent, write):
        ! the search starts where the last one was found, so it is one comparison in the
        ! usual case, not a pass over all of a bundle's datasets.
        do k = 0, this%n_open - 1
            i = mod(this%last_found + k, this%n_open) + 1
            if (this%open_sets(i)%path == path) then
                dataset = this%open_sets(i)%id
                this%last_found = i - 1
                return
            end if
        end do
        call h5dopen_f(this%id, path, dataset, status)
        if (status /= 0) return
        call this%keep_dataset(path, dataset)
    end subroutine open_dataset

    !> Keep the open dataset `dataset` of `path` for later calls (closed at delete or close).
    subroutine keep_dataset(this, path, dataset)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path
        integer(hid_t), intent(in) :: dataset
        type(open_dataset_t), allocatable :: grown(:)
        if (.not. allocated(this%open_sets)) allocate(this%open_sets(16))
        if (this%n_open == size(this%open_sets)) then
            allocate(grown(2 * size(this%open_sets)))
            grown(1:this%n_open) = this%open_sets(1:this%n_open)
            call move_alloc(grown, this%open_sets)
        end if
        this%n_open = this%n_open + 1
        this%open_sets(this%n_open)%path = path
        this%open_sets(this%n_open)%id = dataset
    end subroutine keep_dataset

    !> Close every kept dataset (status: the first failure, 0 if none).
    subroutine close_datasets(this, status)
        class(hdf5_file_t), intent(inout) :: this
        integer, intent(out) :: status
        integer :: i, one
        status = 0
        do i = 1, this%n_open
            call h5dclose_f(this%open_sets(i)%id, one)
            if (status == 0) status = one
            this%open_sets(i)%id = -1
        end do
        this%n_open = 0
        this%last_found = 0
    end subroutine close_datasets


    !> Before creating dataset `path`: the file is open, the groups above exist and the name is
    !> free (a clear message instead of H5Dcreate's failure).
    subroutine prepare_dataset(this, path, routine, err)
        class(hdf5_file_t), intent(inout) :: this
        character(len=*), intent(in) :: path, routine
        type(error_t), allocatable, intent(out) :: err
        integer :: slash, status
        logical :: exists
        call this%check_open(path, routine, err)
        if (allocated(err)) return
        slash = index(path, '/', back=.true.)
        if (slash == len(path) .or. len(path) == 0) then
            call set_error(err, 'invalid dataset name "' // path // '" in "' // this%path // '"', &
                routine, __FILE__, __LINE__)
            return
        end if
        if (slash > 1) then
            call this%create_group(path(1:slash - 1), err)
            if (allocated(err)) return
        end if
        call h5lexists_f(this%id, path, exists, status)
        if (this%failed(status, 'H5Lexists', path, routine, __LINE__, err)) return
        if (exists) then
            call set_error(err, 'cannot create dataset "' // path // '" in "' // this%path // &
                '": the name exists already', routine, __FILE__, __LINE__)
        end if
    end subroutine prepare_dataset

    subroutine check_open(this, object, routine, err)
        class(hdf5_file_t), intent(in) :: this
        character(len=*), intent(in) :: object, routine
        type(error_t), allocatable, intent(out) :: err
        if (.not. this%is_open()) call set_error(err, 'cannot write "' // object // &
            '": no HDF5 file is open', routine, __FILE__, __LINE__)
    end subroutine check_open

    !> True (and `err` set, naming the HDF5 call, the object, the file and, when HDF5's error
    !> stack has it, the system's reason: "No space left on device (errno 28)") when `status`
    !> is a failure of an HDF5 call.
    logical function failed(this, status, call_name, object, routine, line, err)
        class(hdf5_file_t), intent(in) :: this
        integer, intent(in) :: status, line
        character(len=*), intent(in) :: call_name, object, routine
        type(error_t), allocatable, intent(inout) :: err
        character(len=:), allocatable :: file_name, cause
        character(kind=c_char) :: text(512)
        failed = status /= 0
        if (.not. failed) return
        file_name = '(no file)'
        if (allocated(this%path)) file_name = this%path
        cause = ''
        if (c_hdf5_error_cause(text, size(text, kind=c_int)) == 1) &
            cause = ': ' // from_c_string(text)
        call set_error(err, 'HDF5 call ' // call_name // ' failed for "' // object // &
            '" in "' // file_name // '"' // cause, routine, __FILE__, line)
    end function failed

    !> A variable-length UTF-8 string type (h5py reads its attributes as str).
    subroutine new_string_type(string_type, status)
        integer(hid_t), intent(out) :: string_type
        integer, intent(out) :: status
        call h5tcopy_f(H5T_STRING, string_type, status)
        if (status /= 0) then
            string_type = -1
            return
        end if
        call h5tset_cset_f(string_type, H5T_CSET_UTF8_F, status)
    end subroutine new_string_type

    !> Close the identifiers that are open (non-negative); `status` is the first failure.
    subroutine close_all(dataset, space, datatype, status, properties)
        integer(hid_t), intent(in) :: dataset, space, datatype
        integer, intent(out) :: status
        integer(hid_t), intent(in), optional :: properties
        integer :: one
        status = 0
        if (dataset >= 0) then
            call h5dclose_f(dataset, one)
            if (status == 0) status = one
        end if
        if (space >= 0) then
            call h5sclose_f(space, one)
            if (status == 0) status = one
        end if
        if (datatype >= 0) then
            call h5tclose_f(datatype, one)
            if (status == 0) status = one
        end if
        if (present(properties)) then
            if (properties >= 0) then
                call h5pclose_f(properties, one)
                if (status == 0) status = one
            end if
        end if
    end subroutine close_all

    pure logical function optional_true(flag)
        logical, intent(in), optional :: flag
        optional_true = .false.
        if (present(flag)) optional_true = flag
    end function optional_true

end module rs_io_hdf5_file
