!> The XDMF sidecar of a result file (DESIGN.md §7; docs/user/postprocessing.md): a small XML
!> file next to FILE.h5 that lets ParaView (its "XDMF Reader") show the rods over time. It
!> copies no data: every array is a hyperslab of a dataset of the result file (layout of
!> docs/user/output.md), so it is rewritten cheaply whenever the file grows.
!>
!> Interface, for the result writer (call after each flush, once the datasets hold `n` records,
!> and at the end of the run):
!>
!>     type(xdmf_rod_t) :: rods(n_rods)
!>     rods(i) = xdmf_rod_from_fields(name, n_nodes, ',position,directors,velocity,')
!>     !   or, from a whole history: rods(i) = xdmf_rod_from_history(histories(i))
!>     call write_xdmf_sidecar('out/run.h5', rods, times(1:n), err)
!>
!> writes out/run.xdmf (`xdmf_sidecar_path`), replacing it atomically (written to a temporary
!> name, then renamed) so that a reader never sees half a file. `times` are the times of all
!> n records in the file so far, not only of those written at the last flush. The number of
!> records is size(times); the datasets must have exactly that many records (their current
!> extent), since each reference states the full shape of its dataset. The text itself comes
!> from the pure function `xdmf_text(h5_name, rods, times)`, with `h5_name` the result file as
!> the sidecar refers to it (its base name, since the sidecar sits next to it).
!>
!> A rod that does not record `position` has no geometry and is left out; when no rod records
!> it, write_xdmf_sidecar writes nothing (and returns no error): there is nothing to show.
!>
!> Layout (XDMF 3; h5py/C index order, records counted from 0):
!>
!>     Grid "rodsolve"      Collection, Temporal: one child per record k = 0 .. size(times)-1
!>       Grid "record k"    Collection, Spatial; Time Value = times(k+1)
!>         Grid <rod>       Uniform, one per rod that records its position
!>           Topology       Polyline: one polyline through the nodes in order (explicit
!>                          connectivity 0 .. n_nodes-1, inline)
!>           Geometry XYZ   /rods/<rod>/position, start [k,0,0] stride [1,1,1] count [1,n,3]
!>                          (the HyperSlab item starts with the comment "record k", a cache
!>                          key for ParaView's XDMF Reader: see put_hyperslab)
!>           Attribute      "velocity" (Vector, Node): /rods/<rod>/velocity, as position;
!>                          only when the rod has it
!>           Attribute      "d1", "d2", "d3" (Vector, Node): /rods/<rod>/directors
!>                          [records, n, 3, 3], start [k,0,i-1,0] count [1,n,1,3]; only when
!>                          the rod has directors
!>
!> ParaView reads it with its "XDMF Reader" (Xdmf2). Its Xdmf3 readers (Xdmf3ReaderS/T, checked
!> with ParaView 5.11) do not resolve HyperSlab items: they list the times but show no points.
!>
!> Names are escaped for XML. A name or file name may not contain ':' (XDMF separates the file
!> from the dataset path at the first ':'); write_xdmf_sidecar checks this.
module rs_io_xdmf_writer
    use, intrinsic :: iso_c_binding, only: c_char, c_int, c_null_char
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: str
    use rs_model_rod_history, only: rod_history_t
    implicit none
    private

    public :: xdmf_rod_t, xdmf_rod_from_history, xdmf_rod_from_fields, xdmf_text
    public :: write_xdmf_sidecar
    public :: xdmf_sidecar_path, base_name, xml_escape
    public :: xdmf_mode_rod_t, xdmf_modes_text, write_xdmf_modes_sidecar, xdmf_modes_sidecar_path

    !> What the sidecar needs to know of one rod of the result file.
    type :: xdmf_rod_t
        !> The rod's name: its group /rods/<name>/ in the result file.
        character(len=:), allocatable :: name
        !> Nodes of the centreline (the middle dimension of `position`).
        integer :: n_nodes = 0
        !> Whether the file holds /rods/<name>/position; a rod without it is not shown.
        logical :: has_position = .true.
        !> Whether the file holds /rods/<name>/velocity.
        logical :: has_velocity = .false.
        !> Whether the file holds /rods/<name>/directors.
        logical :: has_directors = .false.
    end type xdmf_rod_t

    !> One rod's mode shapes in the result file, for the modes sidecar (docs/user/output.md,
    !> /modes): the group holding its `position` [nodes, 3] and `displacement` [modes, nodes,
    !> 3], and the frequencies (Hz) of its system's modes.
    type :: xdmf_mode_rod_t
        character(len=:), allocatable :: name
        character(len=:), allocatable :: group
        integer :: n_nodes = 0
        real(rk), allocatable :: frequency(:)
    end type xdmf_mode_rod_t

    !> Growing text: `chars(1:length)` is the text so far; the capacity doubles as needed so
    !> that building a long file costs linear time.
    type :: text_buffer_t
        character(len=:), allocatable :: chars
        integer :: length = 0
    end type text_buffer_t

    !> Node numbers per line of the connectivity (lines stay under 100 characters).
    integer, parameter :: numbers_per_line = 12
    character(len=*), parameter :: indent_unit = '  '

    interface
        function c_rename(old, new) bind(C, name='rename') result(status)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: old(*), new(*)
            integer(c_int) :: status
        end function c_rename
    end interface

contains

    !> The sidecar's description of the rod whose history `h` the result file holds: the
    !> fields are present when the history has them (allocated and not empty), as in
    !> write_result_file.
    pure function xdmf_rod_from_history(h) result(rod)
        type(rod_history_t), intent(in) :: h
        type(xdmf_rod_t) :: rod
        rod%name = ''
        if (allocated(h%name)) rod%name = h%name
        rod%n_nodes = h%n_nodes
        rod%has_position = .false.
        if (allocated(h%position)) rod%has_position = size(h%position) > 0
        if (allocated(h%velocity)) rod%has_velocity = size(h%velocity) > 0
        if (allocated(h%directors)) rod%has_directors = size(h%directors) > 0
    end function xdmf_rod_from_history

    !> The sidecar's description of rod `name` with `n_nodes` nodes whose datasets below
    !> /rods/<name>/ are listed in `recorded`, separated by commas ('position,velocity' or
    !> ',position,directors,'; other names are ignored).
    pure function xdmf_rod_from_fields(name, n_nodes, recorded) result(rod)
        character(len=*), intent(in) :: name, recorded
        integer, intent(in) :: n_nodes
        type(xdmf_rod_t) :: rod
        character(len=:), allocatable :: list
        rod%name = name
        rod%n_nodes = n_nodes
        list = ',' // recorded // ','
        rod%has_position = index(list, ',position,') > 0
        rod%has_velocity = index(list, ',velocity,') > 0
        rod%has_directors = index(list, ',directors,') > 0
    end function xdmf_rod_from_fields

    !> The XDMF 3 text describing the result file `h5_name` (as referenced from the sidecar:
    !> normally its base name) with the rods `rods` (those with a position) and the records
    !> at `times` (one record per element, the same for all rods). See the module header for
    !> the layout. Assumes what write_xdmf_sidecar checks: non-empty names without ':',
    !> n_nodes >= 1.
    pure function xdmf_text(h5_name, rods, times) result(text)
        character(len=*), intent(in) :: h5_name
        type(xdmf_rod_t), intent(in) :: rods(:)
        real(rk), intent(in) :: times(:)
        character(len=:), allocatable :: text
        type(text_buffer_t) :: buffer
        integer :: k, r

        call put_opening(buffer, 'rodsolve')
        do k = 0, size(times) - 1
            call put(buffer, 3, '<Grid Name="record ' // str(k) // '" GridType="Collection" ' // &
                'CollectionType="Spatial">')
            call put(buffer, 4, '<Time Value="' // str(times(k + 1)) // '"/>')
            do r = 1, size(rods)
                if (rods(r)%has_position) call put_rod(buffer, 4, h5_name, rods(r), k, &
                    size(times))
            end do
            call put(buffer, 3, '</Grid>')
        end do
        call put_closing(buffer, text)
    end function xdmf_text

    !> The XDMF text of the modes sidecar (FILE.modes.xdmf, docs/user/postprocessing.md): a
    !> temporal collection whose "time" is the mode number 1 .. n (the fewest modes of the
    !> rods' systems), each a spatial collection of the rods in the state the modes are about,
    !> with the attribute "displacement" (the mode shape, a hyperslab of
    !> /modes/<system>/<rod>/displacement) and the mode's frequency (Hz) as Information of
    !> each rod's grid. ParaView animates a mode with Warp By Vector on "displacement" and a
    !> scale factor that oscillates in time.
    pure function xdmf_modes_text(h5_name, rods) result(text)
        character(len=*), intent(in) :: h5_name
        type(xdmf_mode_rod_t), intent(in) :: rods(:)
        character(len=:), allocatable :: text, group, n
        type(text_buffer_t) :: buffer
        integer :: k, r, n_modes
        n_modes = huge(1)
        do r = 1, size(rods)
            n_modes = min(n_modes, size(rods(r)%frequency))
        end do
        call put_opening(buffer, 'modes')
        do k = 0, n_modes - 1
            call put(buffer, 3, '<Grid Name="mode ' // str(k + 1) // '" GridType="Collection" ' // &
                'CollectionType="Spatial">')
            call put(buffer, 4, '<Time Value="' // str(k + 1) // '"/>')
            do r = 1, size(rods)
                group = xml_escape(h5_name, .false.) // ':' // xml_escape(rods(r)%group, .false.) &
                    // '/'
                n = str(rods(r)%n_nodes)
                call put(buffer, 4, '<Grid Name="' // xml_escape(rods(r)%name, .true.) // &
                    '" GridType="Uniform">')
                call put(buffer, 5, '<Information Name="frequency_Hz" Value="' // &
                    str(rods(r)%frequency(k + 1)) // '"/>')
                call put_polyline(buffer, 5, rods(r)%n_nodes)
                call put(buffer, 5, '<Geometry GeometryType="XYZ">')
                call put(buffer, 6, '<DataItem Format="HDF" DataType="Float" Precision="8" ' // &
                    'Dimensions="' // n // ' 3">')
                call put(buffer, 7, group // 'position')
                call put(buffer, 6, '</DataItem>')
                call put(buffer, 5, '</Geometry>')
                call put(buffer, 5, '<Attribute Name="displacement" AttributeType="Vector" ' // &
                    'Center="Node">')
                call put_hyperslab(buffer, 6, group // 'displacement', [k, 0, 0], &
                    [1, rods(r)%n_nodes, 3], [size(rods(r)%frequency), rods(r)%n_nodes, 3])
                call put(buffer, 5, '</Attribute>')
                call put(buffer, 4, '</Grid>')
            end do
            call put(buffer, 3, '</Grid>')
        end do
        call put_closing(buffer, text)
    end function xdmf_modes_text

    !> The uniform grid of one rod at record `k` (0-based) of `n_records`.
    pure subroutine put_rod(buffer, depth, h5_name, rod, k, n_records)
        type(text_buffer_t), intent(inout) :: buffer
        integer, intent(in) :: depth, k, n_records
        character(len=*), intent(in) :: h5_name
        type(xdmf_rod_t), intent(in) :: rod
        character(len=:), allocatable :: group, n
        integer :: i

        group = xml_escape(h5_name, .false.) // ':/rods/' // xml_escape(rod%name, .false.) // '/'
        n = str(rod%n_nodes)
        call put(buffer, depth, '<Grid Name="' // xml_escape(rod%name, .true.) // &
            '" GridType="Uniform">')
        call put_polyline(buffer, depth + 1, rod%n_nodes)
        call put(buffer, depth + 1, '<Geometry GeometryType="XYZ">')
        call put_hyperslab(buffer, depth + 2, group // 'position', [k, 0, 0], &
            [1, rod%n_nodes, 3], [n_records, rod%n_nodes, 3], 'record ' // str(k))
        call put(buffer, depth + 1, '</Geometry>')
        if (rod%has_velocity) then
            call put(buffer, depth + 1, '<Attribute Name="velocity" AttributeType="Vector" ' // &
                'Center="Node">')
            call put_hyperslab(buffer, depth + 2, group // 'velocity', [k, 0, 0], &
                [1, rod%n_nodes, 3], [n_records, rod%n_nodes, 3])
            call put(buffer, depth + 1, '</Attribute>')
        end if
        if (rod%has_directors) then
            do i = 1, 3
                call put(buffer, depth + 1, '<Attribute Name="d' // str(i) // &
                    '" AttributeType="Vector" Center="Node">')
                call put_hyperslab(buffer, depth + 2, group // 'directors', [k, 0, i - 1, 0], &
                    [1, rod%n_nodes, 1, 3], [n_records, rod%n_nodes, 3, 3])
                call put(buffer, depth + 1, '</Attribute>')
            end do
        end if
        call put(buffer, depth, '</Grid>')
    end subroutine put_rod

    !> A HyperSlab DataItem: the block `count` at `start` (stride 1) of the HDF5 dataset
    !> `reference` ("file:/path", escaped) of shape `dims` (all in h5py order). With `key`, a
    !> comment `<!-- key -->` comes first: ParaView's XDMF Reader (Xdmf2) keys its geometry
    !> cache on the text of the first child of the geometry's DataItem, and reports an error
    !> at every step when that child is an element; the key must differ between records, or
    !> it would show the first record's geometry at every time.
    pure subroutine put_hyperslab(buffer, depth, reference, start, count, dims, key)
        type(text_buffer_t), intent(inout) :: buffer
        integer, intent(in) :: depth, start(:), count(:), dims(:)
        character(len=*), intent(in) :: reference
        character(len=*), intent(in), optional :: key
        character(len=:), allocatable :: rank
        rank = str(size(dims))
        call put(buffer, depth, '<DataItem ItemType="HyperSlab" Dimensions="' // &
            joined(count) // '">')
        if (present(key)) call put(buffer, depth + 1, '<!-- ' // key // ' -->')
        call put(buffer, depth + 1, '<DataItem Format="XML" DataType="Int" Precision="4" ' // &
            'Dimensions="3 ' // rank // '">')
        call put(buffer, depth + 2, joined(start))
        call put(buffer, depth + 2, joined(spread(1, 1, size(dims))))
        call put(buffer, depth + 2, joined(count))
        call put(buffer, depth + 1, '</DataItem>')
        call put(buffer, depth + 1, '<DataItem Format="HDF" DataType="Float" Precision="8" ' // &
            'Dimensions="' // joined(dims) // '">')
        call put(buffer, depth + 2, reference)
        call put(buffer, depth + 1, '</DataItem>')
        call put(buffer, depth, '</DataItem>')
    end subroutine put_hyperslab

    !> The document's start, down to the temporal collection `name`.
    pure subroutine put_opening(buffer, name)
        type(text_buffer_t), intent(inout) :: buffer
        character(len=*), intent(in) :: name
        call put(buffer, 0, '<?xml version="1.0" encoding="utf-8"?>')
        call put(buffer, 0, '<Xdmf Version="3.0">')
        call put(buffer, 1, '<Domain>')
        call put(buffer, 2, '<Grid Name="' // name // '" GridType="Collection" ' // &
            'CollectionType="Temporal">')
    end subroutine put_opening

    !> The document's end after the temporal collection, and the whole text.
    pure subroutine put_closing(buffer, text)
        type(text_buffer_t), intent(inout) :: buffer
        character(len=:), allocatable, intent(out) :: text
        call put(buffer, 2, '</Grid>')
        call put(buffer, 1, '</Domain>')
        call put(buffer, 0, '</Xdmf>')
        text = buffer%chars(1:buffer%length)
    end subroutine put_closing

    !> One polyline through n_nodes nodes in order (explicit connectivity, inline).
    pure subroutine put_polyline(buffer, depth, n_nodes)
        type(text_buffer_t), intent(inout) :: buffer
        integer, intent(in) :: depth, n_nodes
        call put(buffer, depth, '<Topology TopologyType="Polyline" NumberOfElements="1" ' // &
            'NodesPerElement="' // str(n_nodes) // '">')
        call put(buffer, depth + 1, '<DataItem Format="XML" DataType="Int" Precision="4" ' // &
            'Dimensions="1 ' // str(n_nodes) // '">')
        call put_connectivity(buffer, depth + 2, n_nodes)
        call put(buffer, depth + 1, '</DataItem>')
        call put(buffer, depth, '</Topology>')
    end subroutine put_polyline

    !> 0 1 ... n-1, `numbers_per_line` to a line.
    pure subroutine put_connectivity(buffer, depth, n_nodes)
        type(text_buffer_t), intent(inout) :: buffer
        integer, intent(in) :: depth, n_nodes
        integer :: first, i
        do first = 0, n_nodes - 1, numbers_per_line
            call put(buffer, depth, joined([(i, i = first, min(first + numbers_per_line, &
                n_nodes) - 1)]))
        end do
    end subroutine put_connectivity

    !> Integers separated by single spaces.
    pure function joined(values) result(text)
        integer, intent(in) :: values(:)
        character(len=:), allocatable :: text
        integer :: i
        text = ''
        do i = 1, size(values)
            if (i > 1) text = text // ' '
            text = text // str(values(i))
        end do
    end function joined

    !> Append one line: `depth` indentation units, `line`, a line feed.
    pure subroutine put(buffer, depth, line)
        type(text_buffer_t), intent(inout) :: buffer
        integer, intent(in) :: depth
        character(len=*), intent(in) :: line
        call append(buffer, repeat(indent_unit, depth) // line // new_line('a'))
    end subroutine put

    pure subroutine append(buffer, text)
        type(text_buffer_t), intent(inout) :: buffer
        character(len=*), intent(in) :: text
        character(len=:), allocatable :: grown
        integer :: needed
        if (.not. allocated(buffer%chars)) then
            allocate(character(len=max(4096, len(text))) :: buffer%chars)
            buffer%length = 0
        end if
        needed = buffer%length + len(text)
        if (needed > len(buffer%chars)) then
            allocate(character(len=max(needed, 2 * len(buffer%chars))) :: grown)
            grown(1:buffer%length) = buffer%chars(1:buffer%length)
            call move_alloc(grown, buffer%chars)
        end if
        buffer%chars(buffer%length + 1:needed) = text
        buffer%length = needed
    end subroutine append

    !> `text` with the XML special characters replaced by entities: & < > always, and the
    !> quotes " ' too when `in_attribute` (attribute values are written in double quotes).
    pure function xml_escape(text, in_attribute) result(escaped)
        character(len=*), intent(in) :: text
        logical, intent(in) :: in_attribute
        character(len=:), allocatable :: escaped
        integer :: i
        escaped = ''
        do i = 1, len(text)
            select case (text(i:i))
            case ('&')
                escaped = escaped // '&amp;'
            case ('<')
                escaped = escaped // '&lt;'
            case ('>')
                escaped = escaped // '&gt;'
            case ('"')
                if (in_attribute) then
                    escaped = escaped // '&quot;'
                else
                    escaped = escaped // '"'
                end if
            case ("'")
                if (in_attribute) then
                    escaped = escaped // '&apos;'
                else
                    escaped = escaped // "'"
                end if
            case default
                escaped = escaped // text(i:i)
            end select
        end do
    end function xml_escape

    !> The sidecar of the result file `h5_path`: its name with the extension .h5 or .hdf5
    !> replaced by .xdmf (out/run.h5 -> out/run.xdmf), or .xdmf appended to any other name.
    pure function xdmf_sidecar_path(h5_path) result(path)
        character(len=*), intent(in) :: h5_path
        character(len=:), allocatable :: path
        integer :: n
        n = len(h5_path)
        if (ends_with(h5_path, '.h5') .and. n > 3) then
            path = h5_path(1:n - 3) // '.xdmf'
        else if (ends_with(h5_path, '.hdf5') .and. n > 5) then
            path = h5_path(1:n - 5) // '.xdmf'
        else
            path = h5_path // '.xdmf'
        end if
    end function xdmf_sidecar_path

    !> The part of `path` after its last '/'.
    pure function base_name(path) result(name)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: name
        name = path(index(path, '/', back=.true.) + 1:)
    end function base_name

    pure logical function ends_with(text, suffix)
        character(len=*), intent(in) :: text, suffix
        ends_with = .false.
        if (len(text) >= len(suffix)) ends_with = text(len(text) - len(suffix) + 1:) == suffix
    end function ends_with

    !> The modes sidecar of a result file: FILE.modes.xdmf next to FILE.h5.
    pure function xdmf_modes_sidecar_path(h5_path) result(path)
        character(len=*), intent(in) :: h5_path
        character(len=:), allocatable :: path
        path = xdmf_sidecar_path(h5_path)
        path = path(1:len(path) - 5) // '.modes.xdmf'
    end function xdmf_modes_sidecar_path

    !> Write the modes sidecar (xdmf_modes_text) next to the result file `h5_path`, replacing
    !> it atomically as write_xdmf_sidecar does.
    subroutine write_xdmf_modes_sidecar(h5_path, rods, err)
        character(len=*), intent(in) :: h5_path
        type(xdmf_mode_rod_t), intent(in) :: rods(:)
        type(error_t), allocatable, intent(out) :: err
        call replace_file(xdmf_modes_sidecar_path(h5_path), xdmf_modes_text(base_name(h5_path), &
            rods), 'XDMF modes sidecar', 'write_xdmf_modes_sidecar', err)
    end subroutine write_xdmf_modes_sidecar

    !> `rods` at the records `times`: xdmf_text(base_name(h5_path), rods, times), written to a
    !> temporary file in the same directory and renamed over the sidecar. The result file
    !> itself is not read; its directory must exist. Fails, writing nothing, for no rods, an
    !> empty or repeated rod name, a name with '/' or ':', a rod without nodes or a result file
    !> name with ':'; and when the file cannot be written or renamed. Writes nothing when no
    !> rod records its position.
    subroutine write_xdmf_sidecar(h5_path, rods, times, err)
        character(len=*), intent(in) :: h5_path
        type(xdmf_rod_t), intent(in) :: rods(:)
        real(rk), intent(in) :: times(:)
        type(error_t), allocatable, intent(out) :: err
        character(len=*), parameter :: routine = 'write_xdmf_sidecar'
        character(len=:), allocatable :: path, problem
        integer :: r, j

        path = xdmf_sidecar_path(h5_path)
        problem = ''
        if (len(base_name(h5_path)) == 0) then
            problem = 'the result file name "' // h5_path // '" has no file part'
        else if (index(base_name(h5_path), ':') > 0) then
            problem = 'the result file name "' // base_name(h5_path) // '" contains '':'', ' // &
                'which XDMF reads as the end of the file name'
        else if (size(rods) == 0) then
            problem = 'no rods given'
        end if
        do r = 1, size(rods)
            if (len(problem) > 0) exit
            if (.not. allocated(rods(r)%name)) then
                problem = 'rod ' // str(r) // ' has no name'
            else if (len(rods(r)%name) == 0 .or. scan(rods(r)%name, '/:') > 0) then
                problem = 'rod ' // str(r) // ' has the name "' // rods(r)%name // &
                    '", which cannot name its group in an XDMF reference (empty, "/" or ":")'
            else if (rods(r)%n_nodes < 1) then
                problem = 'rod "' // rods(r)%name // '" has ' // str(rods(r)%n_nodes) // ' nodes'
            else
                do j = 1, r - 1
                    if (rods(j)%name == rods(r)%name) then
                        problem = 'two rods are named "' // rods(r)%name // '"'
                        exit
                    end if
                end do
            end if
        end do
        if (len(problem) > 0) then
            call set_error(err, 'cannot write the XDMF sidecar "' // path // '": ' // problem, &
                routine, __FILE__, __LINE__)
            return
        end if
        if (.not. any(rods%has_position)) return

        call replace_file(path, xdmf_text(base_name(h5_path), rods, times), 'XDMF sidecar', &
            routine, err)
    end subroutine write_xdmf_sidecar

    !> Write `text` to a temporary file next to `path` and rename it over `path`, so a reader
    !> never sees half a file; `what` names the file in the error.
    subroutine replace_file(path, text, what, routine, err)
        character(len=*), intent(in) :: path, text, what, routine
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: temporary
        character(len=256) :: message
        integer :: unit, status
        temporary = path // '.tmp'
        open(newunit=unit, file=temporary, status='replace', action='write', access='stream', &
            form='unformatted', iostat=status, iomsg=message)
        if (status == 0) then
            write(unit, iostat=status, iomsg=message) text
            if (status == 0) then
                close(unit)
            else
                close(unit, status='delete')
            end if
        end if
        if (status /= 0) then
            call set_error(err, 'cannot write the ' // what // ' "' // temporary // '": ' // &
                trim(message), routine, __FILE__, __LINE__)
            return
        end if
        if (c_rename(temporary // c_null_char, path // c_null_char) /= 0) then
            call set_error(err, 'cannot rename "' // temporary // '" to "' // path // '"', &
                routine, __FILE__, __LINE__)
        end if
    end subroutine replace_file

end module rs_io_xdmf_writer
