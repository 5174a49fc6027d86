#include "rs_assert.h"
!> Unit tests of rs_io_xdmf_writer, the XDMF sidecar of a result file. Here: the text for a
!> small case written out by hand from the layout of the module header, the counts and
!> hyperslabs of a two-rod case, XML escaping, the sidecar's name, the rod description taken
!> from a history, and the errors of write_xdmf_sidecar. The last test writes a result file
!> with write_result_file and its sidecar to xdmf_test/ in the test's working directory
!> (fixture xdmf_file), plus a deliberately wrong sidecar; check_xdmf.py then checks both
!> against the HDF5 file with xml.etree and h5py (and meshio when installed).
module rs_test_io_xdmf_writer
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t
    use rs_model_rod_history, only: rod_history_t
    use rs_io_result_file, only: result_meta_t, write_result_file
    use rs_io_xdmf_writer, only: xdmf_rod_t, xdmf_rod_from_history, xdmf_rod_from_fields, &
        xdmf_text, write_xdmf_sidecar, xdmf_sidecar_path, base_name, xml_escape
    use rs_test_assert, only: run_test, assert_true, assert_equal, assert_contains
    implicit none
    private

    public :: run_all_tests

    !> Where the files go; check_xdmf.py reads them there (tests/unit/io/CMakeLists.txt).
    character(len=*), parameter :: out_dir = 'xdmf_test'
    character, parameter :: lf = new_line('a')

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('single_record_by_hand', test_single_record_by_hand)
        call run_test('two_rods_layout', test_two_rods_layout)
        call run_test('long_rod_connectivity', test_long_rod_connectivity)
        call run_test('escaping', test_escaping)
        call run_test('sidecar_path', test_sidecar_path)
        call run_test('rod_from_history', test_rod_from_history)
        call run_test('rod_from_fields', test_rod_from_fields)
        call run_test('rod_without_position', test_rod_without_position)
        call run_test('sidecar_errors', test_sidecar_errors)
        call run_test('result_file_sidecar', test_result_file_sidecar)
    end subroutine run_all_tests

    pure function rod(name, n_nodes, has_velocity, has_directors) result(r)
        character(len=*), intent(in) :: name
        integer, intent(in) :: n_nodes
        logical, intent(in) :: has_velocity, has_directors
        type(xdmf_rod_t) :: r
        r%name = name
        r%n_nodes = n_nodes
        r%has_velocity = has_velocity
        r%has_directors = has_directors
    end function rod

    !> Occurrences of `fragment` in `text` (not overlapping).
    pure integer function count_of(text, fragment) result(n)
        character(len=*), intent(in) :: text, fragment
        integer :: start, at
        n = 0
        start = 1
        do
            at = index(text(start:), fragment)
            if (at == 0) exit
            n = n + 1
            start = start + at - 1 + len(fragment)
            if (start > len(text)) exit
        end do
    end function count_of

    !> One rod of two nodes, one record at t = 1.5, no optional fields: the whole text, written
    !> by hand from the layout in the header of rs_io_xdmf_writer.
    subroutine test_single_record_by_hand()
        character(len=:), allocatable :: expected, text
        expected = &
            '<?xml version="1.0" encoding="utf-8"?>' // lf // &
            '<Xdmf Version="3.0">' // lf // &
            '  <Domain>' // lf // &
            '    <Grid Name="rodsolve" GridType="Collection" CollectionType="Temporal">' // lf // &
            '      <Grid Name="record 0" GridType="Collection" ' // &
            'CollectionType="Spatial">' // lf // &
            '        <Time Value="1.5"/>' // lf // &
            '        <Grid Name="r" GridType="Uniform">' // lf // &
            '          <Topology TopologyType="Polyline" NumberOfElements="1" ' // &
            'NodesPerElement="2">' // lf // &
            '            <DataItem Format="XML" DataType="Int" Precision="4" ' // &
            'Dimensions="1 2">' // lf // &
            '              0 1' // lf // &
            '            </DataItem>' // lf // &
            '          </Topology>' // lf // &
            '          <Geometry GeometryType="XYZ">' // lf // &
            '            <DataItem ItemType="HyperSlab" Dimensions="1 2 3">' // lf // &
            '              <!-- record 0 -->' // lf // &
            '              <DataItem Format="XML" DataType="Int" Precision="4" ' // &
            'Dimensions="3 3">' // lf // &
            '                0 0 0' // lf // &
            '                1 1 1' // lf // &
            '                1 2 3' // lf // &
            '              </DataItem>' // lf // &
            '              <DataItem Format="HDF" DataType="Float" Precision="8" ' // &
            'Dimensions="1 2 3">' // lf // &
            '                f.h5:/rods/r/position' // lf // &
            '              </DataItem>' // lf // &
            '            </DataItem>' // lf // &
            '          </Geometry>' // lf // &
            '        </Grid>' // lf // &
            '      </Grid>' // lf // &
            '    </Grid>' // lf // &
            '  </Domain>' // lf // &
            '</Xdmf>' // lf
        text = xdmf_text('f.h5', [rod('r', 2, .false., .false.)], [1.5_rk])
        CHECK_EQUAL(text, expected, 'the whole text')
    end subroutine test_single_record_by_hand

    !> 'arm' (5 nodes, velocity and directors) and 'tail' (7 nodes, neither) at 3 records.
    subroutine test_two_rods_layout()
        character(len=:), allocatable :: text, line, expected
        integer :: start, end, longest, k
        logical :: even_indent
        text = xdmf_text('two_rods.h5', [rod('arm', 5, .true., .true.), &
            rod('tail', 7, .false., .false.)], [0.0_rk, 0.25_rk, 0.5_rk])
        CHECK_EQUAL(count_of(text, 'CollectionType="Temporal"'), 1, 'one temporal collection')
        CHECK_EQUAL(count_of(text, 'CollectionType="Spatial"'), 3, 'a spatial one per record')
        CHECK_EQUAL(count_of(text, '<Time '), 3, 'a time per record')
        CHECK_EQUAL(count_of(text, '<Time Value="0.25"/>'), 1, 'time of record 1')
        CHECK_EQUAL(count_of(text, '<Grid Name="arm" GridType="Uniform">'), 3, 'arm grids')
        CHECK_EQUAL(count_of(text, '<Grid Name="tail" GridType="Uniform">'), 3, 'tail grids')
        CHECK_EQUAL(count_of(text, 'two_rods.h5:/rods/arm/position'), 3, 'arm position')
        CHECK_EQUAL(count_of(text, 'two_rods.h5:/rods/tail/position'), 3, 'tail position')
        CHECK_EQUAL(count_of(text, 'two_rods.h5:/rods/arm/velocity'), 3, 'arm velocity')
        CHECK_EQUAL(count_of(text, 'two_rods.h5:/rods/arm/directors'), 9, 'd1, d2, d3 of arm')
        CHECK_EQUAL(count_of(text, '/rods/tail/velocity'), 0, 'no velocity for tail')
        CHECK_EQUAL(count_of(text, '/rods/tail/directors'), 0, 'no directors for tail')
        k = count_of(text, '<Attribute Name="d2" AttributeType="Vector" Center="Node">')
        CHECK_EQUAL(k, 3, 'd2 attributes')
        CHECK_EQUAL(count_of(text, 'NodesPerElement="7"'), 3, 'polyline through the 7 nodes')
        CHECK_EQUAL(count_of(text, '<!-- '), 6, 'a cache key in each geometry, nowhere else')
        CHECK_EQUAL(count_of(text, '<!-- record 2 -->'), 2, 'the key names the record')
        CHECK_EQUAL(count_of(text, '0 1 2 3 4 5 6' // lf), 3, 'tail connectivity')
        ! Record 2 of d3 of arm: start [2, 0, 2, 0], count [1, 5, 1, 3] of the [3, 5, 3, 3] set.
        expected = '<Attribute Name="d3" AttributeType="Vector" Center="Node">' // lf // &
            repeat(' ', 12) // '<DataItem ItemType="HyperSlab" Dimensions="1 5 1 3">' // lf // &
            repeat(' ', 14) // '<DataItem Format="XML" DataType="Int" Precision="4" ' // &
            'Dimensions="3 4">' // lf // repeat(' ', 16) // '2 0 2 0' // lf // &
            repeat(' ', 16) // '1 1 1 1' // lf // repeat(' ', 16) // '1 5 1 3' // lf // &
            repeat(' ', 14) // '</DataItem>' // lf // repeat(' ', 14) // &
            '<DataItem Format="HDF" DataType="Float" Precision="8" Dimensions="3 5 3 3">' // &
            lf // repeat(' ', 16) // 'two_rods.h5:/rods/arm/directors' // lf
        CHECK_CONTAINS(text, expected, 'd3 at record 2')
        expected = '1 1 1' // lf // repeat(' ', 16) // '1 7 3' // lf // &
            repeat(' ', 14) // '</DataItem>' // lf // repeat(' ', 14) // &
            '<DataItem Format="HDF" DataType="Float" Precision="8" Dimensions="3 7 3">' // &
            lf // repeat(' ', 16) // 'two_rods.h5:/rods/tail/position'
        CHECK_CONTAINS(text, expected, 'tail position slab')
        CHECK_EQUAL(count_of(text, '<Grid '), count_of(text, '</Grid>'), 'Grid tags balance')
        k = count_of(text, '<DataItem ')
        CHECK_EQUAL(k, count_of(text, '</DataItem>'), 'DataItem tags balance')
        k = count_of(text, '<Attribute ')
        CHECK_EQUAL(k, count_of(text, '</Attribute>'), 'Attribute tags balance')

        longest = 0
        even_indent = .true.
        start = 1
        do while (start <= len(text))
            end = start + index(text(start:), lf) - 2
            line = text(start:end)
            longest = max(longest, len(line))
            k = verify(line, ' ')
            if (k > 0) even_indent = even_indent .and. mod(k - 1, 2) == 0
            start = end + 2
        end do
        CHECK_TRUE(longest < 100, 'lines shorter than 100 characters')
        CHECK_TRUE(even_indent, 'indented by two spaces a level')
        CHECK_EQUAL(text(len(text):), lf, 'ends with a line feed')
    end subroutine test_two_rods_layout

    !> 30 nodes: the connectivity is 0 .. 29 in order, 12 to a line.
    subroutine test_long_rod_connectivity()
        character(len=:), allocatable :: text, expected
        text = xdmf_text('f.h5', [rod('long', 30, .false., .false.)], [0.0_rk])
        expected = 'Dimensions="1 30">' // lf // repeat(' ', 14) // &
            '0 1 2 3 4 5 6 7 8 9 10 11' // lf // repeat(' ', 14) // &
            '12 13 14 15 16 17 18 19 20 21 22 23' // lf // repeat(' ', 14) // &
            '24 25 26 27 28 29' // lf // repeat(' ', 12) // '</DataItem>'
        CHECK_CONTAINS(text, expected, 'connectivity')
    end subroutine test_long_rod_connectivity

    subroutine test_escaping()
        character(len=:), allocatable :: text
        text = 'a&lt;b&gt;&amp;&quot;c&apos;d'
        CHECK_EQUAL(xml_escape('a<b>&"c''d', .true.), text, 'attribute value')
        CHECK_EQUAL(xml_escape('a<b>&"c''d', .false.), 'a&lt;b&gt;&amp;"c''d', 'text')
        CHECK_EQUAL(xml_escape('', .true.), '', 'empty')
        text = xdmf_text('r&d <1>.h5', [rod('x"&y', 2, .true., .false.)], [0.0_rk])
        CHECK_CONTAINS(text, '<Grid Name="x&quot;&amp;y" GridType="Uniform">', 'grid name')
        CHECK_CONTAINS(text, 'r&amp;d &lt;1&gt;.h5:/rods/x"&amp;y/position', 'geometry reference')
        CHECK_CONTAINS(text, 'r&amp;d &lt;1&gt;.h5:/rods/x"&amp;y/velocity', 'velocity reference')
        CHECK_EQUAL(count_of(text, 'x"&y'), 0, 'no raw ampersand')
    end subroutine test_escaping

    subroutine test_sidecar_path()
        CHECK_EQUAL(xdmf_sidecar_path('out/run.h5'), 'out/run.xdmf', '.h5')
        CHECK_EQUAL(xdmf_sidecar_path('/a/b/run.hdf5'), '/a/b/run.xdmf', '.hdf5')
        CHECK_EQUAL(xdmf_sidecar_path('run'), 'run.xdmf', 'no extension')
        CHECK_EQUAL(xdmf_sidecar_path('run.H5'), 'run.H5.xdmf', 'other extension')
        CHECK_EQUAL(xdmf_sidecar_path('.h5'), '.h5.xdmf', 'a bare extension is a name')
        CHECK_EQUAL(base_name('out/sub/run.h5'), 'run.h5', 'base name')
        CHECK_EQUAL(base_name('run.h5'), 'run.h5', 'base name without directory')
        CHECK_EQUAL(base_name('out/'), '', 'directory only')
    end subroutine test_sidecar_path

    subroutine test_rod_from_history()
        type(rod_history_t) :: h
        type(xdmf_rod_t) :: r
        call h%init('arm', 'ph_director', 5, 8, 3)
        r = xdmf_rod_from_history(h)
        CHECK_EQUAL(r%name, 'arm', 'name')
        CHECK_EQUAL(r%n_nodes, 5, 'nodes')
        CHECK_TRUE(r%has_position, 'position')
        CHECK_TRUE(r%has_velocity .and. r%has_directors, 'velocity and directors')
        deallocate(h%velocity)
        deallocate(h%directors)
        allocate(h%directors(3, 3, 5, 0))
        r = xdmf_rod_from_history(h)
        CHECK_TRUE(r%has_position, 'position still')
        CHECK_TRUE(.not. r%has_velocity, 'unallocated velocity is absent')
        CHECK_TRUE(.not. r%has_directors, 'empty directors are absent')
        deallocate(h%position)
        r = xdmf_rod_from_history(h)
        CHECK_TRUE(.not. r%has_position, 'unallocated position is absent')
    end subroutine test_rod_from_history

    subroutine test_rod_from_fields()
        type(xdmf_rod_t) :: r
        r = xdmf_rod_from_fields('arm', 5, ',position,directors,stress,')
        CHECK_EQUAL(r%name, 'arm', 'name')
        CHECK_EQUAL(r%n_nodes, 5, 'nodes')
        CHECK_TRUE(r%has_position .and. r%has_directors, 'position and directors')
        CHECK_TRUE(.not. r%has_velocity, 'no velocity')
        r = xdmf_rod_from_fields('arm', 5, 'velocity,director_velocity')
        CHECK_TRUE(r%has_velocity, 'velocity without surrounding commas')
        CHECK_TRUE(.not. (r%has_position .or. r%has_directors), 'director_velocity is not that')
        r = xdmf_rod_from_fields('arm', 5, '')
        CHECK_TRUE(.not. (r%has_position .or. r%has_velocity .or. r%has_directors), 'nothing')
    end subroutine test_rod_from_fields

    !> A rod without position is left out; with no rod to show, no sidecar is written.
    subroutine test_rod_without_position()
        type(xdmf_rod_t) :: rods(2)
        type(error_t), allocatable :: err
        character(len=:), allocatable :: text
        logical :: exists
        rods(1) = rod('arm', 5, .true., .true.)
        rods(2) = rod('tail', 7, .true., .false.)
        rods(2)%has_position = .false.
        text = xdmf_text('f.h5', rods, [0.0_rk, 1.0_rk])
        CHECK_EQUAL(count_of(text, '<Grid Name="arm"'), 2, 'arm shown')
        CHECK_EQUAL(count_of(text, 'tail'), 0, 'tail left out')
        rods(1)%has_position = .false.
        call execute_command_line('mkdir -p ' // out_dir)
        call write_xdmf_sidecar(out_dir // '/hidden.h5', rods, [0.0_rk], err)
        CHECK_TRUE(.not. allocated(err), 'not an error')
        inquire(file=out_dir // '/hidden.xdmf', exist=exists)
        CHECK_TRUE(.not. exists, 'no sidecar without positions')
    end subroutine test_rod_without_position

    subroutine test_sidecar_errors()
        type(error_t), allocatable :: err
        type(xdmf_rod_t) :: rods(2)
        logical :: exists
        integer :: unit
        call execute_command_line('mkdir -p ' // out_dir)
        rods(1) = rod('arm', 5, .true., .true.)
        rods(2) = rod('tail', 7, .false., .false.)

        call write_xdmf_sidecar(out_dir // '/a:b.h5', rods, [0.0_rk], err)
        call expect(':', 'a:b.h5')
        call write_xdmf_sidecar(out_dir // '/none.h5', rods(1:0), [0.0_rk], err)
        call expect('no rods given', 'none.xdmf')
        rods(2)%name = 'arm'
        call write_xdmf_sidecar(out_dir // '/twice.h5', rods, [0.0_rk], err)
        call expect('two rods are named "arm"', 'twice.xdmf')
        rods(2)%name = 'a/b'
        call write_xdmf_sidecar(out_dir // '/slash.h5', rods, [0.0_rk], err)
        call expect('"a/b"', 'slash.xdmf')
        rods(2)%name = ''
        call write_xdmf_sidecar(out_dir // '/empty.h5', rods, [0.0_rk], err)
        call expect('rod 2 has the name ""', 'empty.xdmf')
        rods(2)%name = 'tail'
        rods(2)%n_nodes = 0
        call write_xdmf_sidecar(out_dir // '/nodes.h5', rods, [0.0_rk], err)
        call expect('rod "tail" has 0 nodes', 'nodes.xdmf')
        rods(2)%n_nodes = 7
        call write_xdmf_sidecar(out_dir // '/', rods, [0.0_rk], err)
        call expect('has no file part', '')
        inquire(file=out_dir // '/nodes.xdmf', exist=exists)
        CHECK_TRUE(.not. exists, 'nothing written for invalid rods')

        ! A directory under a regular file cannot be written to, not even by root.
        open(newunit=unit, file=out_dir // '/not_a_directory', status='replace')
        close(unit)
        call write_xdmf_sidecar(out_dir // '/not_a_directory/run.h5', rods, [0.0_rk], err)
        call expect('cannot write the XDMF sidecar "' // out_dir // &
            '/not_a_directory/run.xdmf.tmp"', 'run.xdmf')
    contains
        subroutine expect(fragment, file)
            character(len=*), intent(in) :: fragment, file
            CHECK_TRUE(allocated(err), 'an error: ' // fragment)
            if (.not. allocated(err)) return
            CHECK_CONTAINS(err%message, fragment, 'message')
            CHECK_CONTAINS(err%message, file, 'names the file')
            deallocate(err)
        end subroutine expect
    end subroutine test_sidecar_errors

    !> Rod k of a synthetic result file, as in test_result_file.F90: 'arm' (k = 1, 5 nodes,
    !> every field) or 'tail' (k = 2, 7 nodes, no velocity and no directors), turning about e3
    !> and rising; `n_stored` of room for n_stored + 2 records.
    function synthetic_rod(k, n_stored) result(h)
        integer, intent(in) :: k, n_stored
        type(rod_history_t) :: h
        integer :: a, j, i
        real(rk) :: t, s, psi
        if (k == 1) then
            call h%init('arm', 'ph_director', 5, 4, n_stored + 2)
        else
            call h%init('tail', 'se3_strand', 7, 6, n_stored + 2)
        end if
        do a = 1, h%n_nodes
            h%mesh(a) = k * (a - 1.0_rk) / (h%n_nodes - 1)
        end do
        do j = 1, n_stored
            if (h%next_record() /= j) error stop 'synthetic_rod: capacity'
            t = 0.25_rk * (j - 1)
            h%time(j) = t
            h%dt(j) = 0.25_rk
            do a = 1, h%n_nodes
                s = h%mesh(a)
                psi = 0.5_rk * k * t
                h%position(:, a, j) = [s * cos(psi), s * sin(psi), 0.1_rk * t]
                h%velocity(:, a, j) = [-s * sin(psi), s * cos(psi), 0.1_rk]
                do i = 1, 3
                    h%directors(:, i, a, j) = 0.0_rk
                    h%directors(i, i, a, j) = 1.0_rk + j + 10 * a + 100 * i
                end do
            end do
        end do
        if (k == 2) deallocate(h%velocity, h%directors, h%director_velocity)
    end function synthetic_rod

    !> xdmf_test/two_rods.h5 and its sidecar two_rods.xdmf (checked by check_xdmf.py), and
    !> broken.xdmf: the sidecar of a file whose 'arm' had 6 nodes and one more record, which
    !> check_xdmf.py must reject.
    subroutine test_result_file_sidecar()
        integer, parameter :: n_stored = 4
        type(rod_history_t) :: histories(2)
        type(xdmf_rod_t) :: rods(2)
        type(result_meta_t) :: meta
        type(error_t), allocatable :: err
        character(len=*), parameter :: h5_path = out_dir // '/two_rods.h5'
        character(len=:), allocatable :: written
        logical :: exists
        integer :: unit, size_bytes, i

        histories(1) = synthetic_rod(1, n_stored)
        histories(2) = synthetic_rod(2, n_stored)
        meta%title = 'xdmf sidecar test'
        meta%command_line = 'test_xdmf_writer'
        call write_result_file(h5_path, meta, histories, err)
        CHECK_TRUE(.not. allocated(err), 'write_result_file')
        if (allocated(err)) then
            print '(a)', err%describe()
            return
        end if
        do i = 1, 2
            rods(i) = xdmf_rod_from_history(histories(i))
        end do
        CHECK_TRUE(rods(1)%has_velocity .and. rods(1)%has_directors, 'arm has both fields')
        CHECK_TRUE(.not. (rods(2)%has_velocity .or. rods(2)%has_directors), 'tail has neither')

        ! Twice: the second call replaces the first file.
        call write_xdmf_sidecar(h5_path, rods, histories(1)%time(1:n_stored - 1), err)
        CHECK_TRUE(.not. allocated(err), 'write_xdmf_sidecar, 3 records')
        call write_xdmf_sidecar(h5_path, rods, histories(1)%time(1:n_stored), err)
        CHECK_TRUE(.not. allocated(err), 'write_xdmf_sidecar, 4 records')
        if (allocated(err)) then
            print '(a)', err%describe()
            return
        end if
        inquire(file=out_dir // '/two_rods.xdmf.tmp', exist=exists)
        CHECK_TRUE(.not. exists, 'no temporary file left')
        inquire(file=out_dir // '/two_rods.xdmf', size=size_bytes)
        CHECK_TRUE(size_bytes > 0, 'the sidecar exists')
        if (size_bytes <= 0) return
        allocate(character(len=size_bytes) :: written)
        open(newunit=unit, file=out_dir // '/two_rods.xdmf', access='stream', &
            form='unformatted', action='read')
        read(unit) written
        close(unit)
        exists = written == xdmf_text('two_rods.h5', rods, histories(1)%time(1:n_stored))
        CHECK_TRUE(exists, 'the file holds xdmf_text of the base name and the 4 records')

        rods(1)%n_nodes = 6
        open(newunit=unit, file=out_dir // '/broken.xdmf', access='stream', &
            form='unformatted', status='replace', action='write')
        write(unit) xdmf_text('two_rods.h5', rods, [histories(1)%time(1:n_stored), 1.0_rk])
        close(unit)
    end subroutine test_result_file_sidecar

end module rs_test_io_xdmf_writer

!> Test program: runs the tests of rs_test_io_xdmf_writer; exits non-zero if any failed.
program test_xdmf_writer
    use rs_test_io_xdmf_writer, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_xdmf_writer
