#include "rs_assert.h"
!> Unit tests of rs_io_result_file (write_result_file) and of the checked HDF5 layer under it
!> (rs_io_hdf5_file). Two synthetic rods move in closed form (a rigid rotation about e3 with a
!> rise along e3); the file is written to result_file_test/nested/two_rods.h5 in the test's
!> working directory (the missing directories are created), and check_result_file.py reads it
!> back with h5py and compares with the same closed form. Here: the return status of good
!> writes, and the errors for an unwritable path, rods that do not share a time grid, duplicate
!> or unusable names and a history with fewer records than n_stored (stress, strains,
!> branch_stress, dissipated, tie_force), and the bundle series (contact, ties) with their
!> `&output fields` selection.
module rs_test_io_result_file
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t
    use rs_model_rod_history, only: rod_history_t
    use rs_io_hdf5_file, only: hdf5_file_t
    use rs_io_result_file, only: result_meta_t, write_result_file, result_schema_version, &
        rod_layout_t, layout_of, prepare_result_file, result_writer_t, unknown_fields
    use rs_test_assert, only: run_test, assert_true, assert_equal, assert_contains
    implicit none
    private

    public :: run_all_tests

    !> Where the files go; check_result_file.py and test_rodplot.py read them there.
    character(len=*), parameter :: out_dir = 'result_file_test'
    character(len=*), parameter :: result_path = out_dir // '/nested/two_rods.h5'
    character(len=*), parameter :: layer_path = out_dir // '/layer.h5'
    character(len=*), parameter :: selection_path = out_dir // '/selection.h5'
    character(len=*), parameter :: kept_path = out_dir // '/kept.h5'

    ! The closed form; check_result_file.py has the same definitions.
    integer, parameter :: n_stored = 8
    real(rk), parameter :: time_step = 0.25_rk

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('two_rods', test_two_rods)
        call run_test('unwritable_path', test_unwritable_path)
        call run_test('time_grids_differ', test_time_grids_differ)
        call run_test('bad_names', test_bad_names)
        call run_test('short_history', test_short_history)
        call run_test('hdf5_layer', test_hdf5_layer)
        call run_test('hdf5_kept_datasets', test_hdf5_kept_datasets)
        call run_test('bundle_series_selection', test_bundle_series_selection)
    end subroutine run_all_tests

    !> Rod k of the synthetic scene: 'arm' (k = 1: 5 nodes, 8 stress points, 2 Maxwell
    !> branches, length 1, room for 10 records, every array) or 'tail' (k = 2: 7 nodes, 6 stress
    !> points, no branches, length 2, room for 12 records, no director velocity, an empty
    !> constraint residual). Only 'arm' is a rod of a bundle: it has the contact and tie series
    !> (init_coupling). The records after n_stored hold garbage that must not reach the file.
    function synthetic_rod(k) result(h)
        integer, intent(in) :: k
        type(rod_history_t) :: h
        integer :: n_nodes, n_points, a, p, c, i, j, b
        real(rk) :: length, omega, rise, t, s, psi, rotation(3, 3), rate(3, 3)

        if (k == 1) then
            call h%init('arm', 'ph_director', 5, 8, 10, n_branches=2)
        else
            call h%init('tail', 'se3_strand', 7, 6, 12)
        end if
        n_nodes = h%n_nodes
        n_points = h%n_stress_points
        length = real(k, rk)
        omega = 0.5_rk * k
        rise = 0.1_rk * k
        h%position = -999.0_rk
        h%directors = -999.0_rk
        h%time = -999.0_rk
        h%kinetic = -999.0_rk
        h%strains = -999.0_rk
        h%dissipated = -999.0_rk
        h%newton_iterations = -999
        if (allocated(h%branch_stress)) h%branch_stress = -999.0_rk
        if (k == 1) then
            call h%init_coupling(10)
            h%contact_energy = -999.0_rk
            h%penetration = -999.0_rk
            h%contact_force = -999.0_rk
            h%tie_force = -999.0_rk
            h%tie_moment = -999.0_rk
            h%friction_force = -999.0_rk
            h%slip_speed = -999.0_rk
        end if
        do a = 1, n_nodes
            h%mesh(a) = length * (a - 1) / (n_nodes - 1)
        end do
        do p = 1, n_points
            h%stress_mesh(p) = length * (p - 0.5_rk) / n_points
        end do
        do j = 1, n_stored
            if (h%next_record() /= j) error stop 'synthetic_rod: capacity'
            t = time_step * (j - 1)
            h%time(j) = t
            do a = 1, n_nodes
                s = h%mesh(a)
                h%position(:, a, j) = [s * cos(omega * t), s * sin(omega * t), rise * t]
                h%velocity(:, a, j) = [-s * omega * sin(omega * t), s * omega * cos(omega * t), &
                    rise]
                psi = omega * t + 0.1_rk * (a - 1)
                rotation = reshape([cos(psi), sin(psi), 0.0_rk, -sin(psi), cos(psi), 0.0_rk, &
                    0.0_rk, 0.0_rk, 1.0_rk], [3, 3])
                rate = omega * reshape([-sin(psi), cos(psi), 0.0_rk, -cos(psi), -sin(psi), &
                    0.0_rk, 0.0_rk, 0.0_rk, 0.0_rk], [3, 3])
                do i = 1, 3
                    h%directors(:, i, a, j) = rotation(:, i)
                    h%director_velocity(:, i, a, j) = rate(:, i)
                end do
            end do
            do p = 1, n_points
                do c = 1, 6
                    h%stress(c, p, j) = c + 10.0_rk * p + 100.0_rk * t + 1000.0_rk * k
                    h%strains(c, p, j) = 1.0e-3_rk * (c + 10.0_rk * p) + 0.1_rk * t * k
                    do b = 1, h%n_branches
                        h%branch_stress(c, p, b, j) = 0.1_rk * b * h%stress(c, p, j)
                    end do
                end do
            end do
            h%kinetic(j) = k * (1.0_rk + t**2)
            h%strain(j) = k * cos(t)
            h%total(j) = h%kinetic(j) + h%strain(j)
            h%external_work(j) = 0.01_rk * k * (j - 1)
            h%balance_error(j) = 1.0e-14_rk * k * j * (-1)**j
            h%dissipated(j) = 0.001_rk * k * j
            h%actuator_work(j) = -0.002_rk * k * (j - 1)
            h%linear_momentum(:, j) = k * [1.0_rk, 2.0_rk, 3.0_rk] * (1.0_rk + t)
            h%angular_momentum(:, j) = k * [0.5_rk, -0.5_rk, t]
            h%center_of_mass(:, j) = [k * t, 0.0_rk, 0.5_rk * length]
            h%constraint_residual(j) = 1.0e-15_rk * j
            h%newton_iterations(j) = j + k
            h%newton_residual(j) = 1.0e-10_rk / j
            h%dt(j) = time_step
            if (k == 1) then
                h%contact_energy(j) = 1.0e-3_rk * j
                h%penetration(j) = 1.0e-5_rk * mod(j, 3)
                h%contact_force(:, j) = [real(j, rk), -2.0_rk * j, 0.5_rk]
                do a = 1, 2
                    h%tie_force(:, a, j) = [real(a, rk), 10.0_rk * j, -1.0_rk * a * j]
                    h%tie_moment(:, a, j) = [0.1_rk * a * j, -real(a, rk), 0.5_rk * j]
                end do
                h%friction_force(:, j) = [0.25_rk * j, 0.0_rk, -1.0_rk]
                h%slip_speed(j) = 1.0e-3_rk * j
            end if
        end do
        if (k == 2) then
            deallocate(h%director_velocity)
            deallocate(h%constraint_residual)
            allocate(h%constraint_residual(0))
        end if
    end function synthetic_rod

    function synthetic_meta() result(meta)
        type(result_meta_t) :: meta
        character, parameter :: lf = new_line('a')
        meta%title = 'two synthetic rods'
        meta%command_line = 'test_result_file --synthetic'
        meta%n_ranks = 3
        meta%petsc_version = 'Petsc Release Version 3.18.test'
        meta%mpi_version = 'test MPI 1.0'
        ! Non-ASCII (UTF-8 e-acute), a tab and blank lines must come back verbatim.
        meta%input_text = '! scene of the synthetic test, caf' // char(195) // char(169) // lf // &
            '&rod name = ''arm'', n_elements = 4 /' // lf // lf // achar(9) // &
            '&rod name = ''tail'' /' // lf
        meta%input_resolved = '&run' // lf // '    title = ''two synthetic rods''' // lf // &
            '/' // lf
        meta%petsc_options = '-snes_rtol 0 -snes_stol 0'
    end function synthetic_meta

    !> The full file; also the input of check_result_file.py and test_rodplot.py.
    subroutine test_two_rods()
        type(rod_history_t) :: rods(2)
        type(error_t), allocatable :: err
        logical :: exists
        rods(1) = synthetic_rod(1)
        rods(2) = synthetic_rod(2)
        call execute_command_line('rm -rf ' // out_dir)
        call write_result_file(result_path, synthetic_meta(), rods, err)
        CHECK_TRUE(.not. allocated(err), 'write_result_file succeeds')
        if (allocated(err)) print '(a)', err%describe()
        inquire(file=result_path, exist=exists)
        CHECK_TRUE(exists, 'the file and its missing directories are created')
        CHECK_EQUAL(result_schema_version, 2, 'schema version')
    end subroutine test_two_rods

    !> A path under a regular file cannot be created, not even by root; /proc takes no files.
    subroutine test_unwritable_path()
        type(rod_history_t) :: rods(1)
        type(error_t), allocatable :: err
        integer :: unit
        rods(1) = synthetic_rod(1)
        call execute_command_line('mkdir -p ' // out_dir)
        open(newunit=unit, file=out_dir // '/not_a_directory', status='replace')
        write(unit, '(a)') 'a regular file'
        close(unit)
        call write_result_file(out_dir // '/not_a_directory/sub/out.h5', synthetic_meta(), rods, &
            err)
        CHECK_TRUE(allocated(err), 'a directory under a regular file is an error')
        if (.not. allocated(err)) return
        CHECK_CONTAINS(err%message, 'cannot create the directory', 'message')
        CHECK_CONTAINS(err%message, out_dir // '/not_a_directory/sub', 'names the directory')
        CHECK_CONTAINS(err%message, 'out.h5', 'names the file')
        deallocate(err)
        call write_result_file('/proc/rodsolve_test_result.h5', synthetic_meta(), rods, err)
        CHECK_TRUE(allocated(err), '/proc is not writable')
        if (.not. allocated(err)) return
        CHECK_CONTAINS(err%message, '/proc/rodsolve_test_result.h5', 'names the file')
    end subroutine test_unwritable_path

    !> All rods share the time grid of their records; otherwise no file is written.
    subroutine test_time_grids_differ()
        type(rod_history_t) :: rods(2)
        type(error_t), allocatable :: err
        logical :: exists
        character(len=*), parameter :: path = out_dir // '/mismatch.h5'
        rods(1) = synthetic_rod(1)
        rods(2) = synthetic_rod(2)
        rods(2)%time(3) = rods(2)%time(3) + 1.0e-3_rk
        call write_result_file(path, synthetic_meta(), rods, err)
        CHECK_TRUE(allocated(err), 'different times are an error')
        if (allocated(err)) then
            CHECK_CONTAINS(err%message, 'do not share the time grid: record 3', 'message')
            CHECK_CONTAINS(err%message, '"tail"', 'names the rod')
        end if
        inquire(file=path, exist=exists)
        CHECK_TRUE(.not. exists, 'no file for an inconsistent history')
        if (allocated(err)) deallocate(err)
        rods(2) = synthetic_rod(2)
        rods(2)%n_stored = n_stored - 1
        call write_result_file(path, synthetic_meta(), rods, err)
        CHECK_TRUE(allocated(err), 'different record counts are an error')
        if (allocated(err)) CHECK_CONTAINS(err%message, '8 and 7 stored records', 'message')
    end subroutine test_time_grids_differ

    subroutine test_bad_names()
        type(rod_history_t) :: rods(2)
        type(error_t), allocatable :: err
        rods(1) = synthetic_rod(1)
        rods(2) = synthetic_rod(2)
        rods(2)%name = 'arm'
        call write_result_file(out_dir // '/names.h5', synthetic_meta(), rods, err)
        CHECK_TRUE(allocated(err), 'duplicate names are an error')
        if (allocated(err)) CHECK_CONTAINS(err%message, 'two rods are named "arm"', 'message')
        if (allocated(err)) deallocate(err)
        rods(2)%name = 'a/b'
        call write_result_file(out_dir // '/names.h5', synthetic_meta(), rods, err)
        CHECK_TRUE(allocated(err), 'a name with "/" is an error')
        if (allocated(err)) CHECK_CONTAINS(err%message, '"a/b"', 'message')
        if (allocated(err)) deallocate(err)
        call write_result_file(out_dir // '/names.h5', synthetic_meta(), rods(1:0), err)
        CHECK_TRUE(allocated(err), 'no rods is an error')
    end subroutine test_bad_names

    !> A formulation whose array holds fewer records than n_stored is caught, not read beyond.
    subroutine test_short_history()
        type(rod_history_t) :: rods(1)
        type(error_t), allocatable :: err
        logical :: exists
        character(len=*), parameter :: path = out_dir // '/short.h5'
        integer :: ns
        rods(1) = synthetic_rod(1)
        ns = rods(1)%n_stress_points
        deallocate(rods(1)%stress)
        allocate(rods(1)%stress(6, ns, n_stored - 2), source=0.0_rk)
        call expect_short('stress')
        rods(1) = synthetic_rod(1)
        deallocate(rods(1)%strains)
        allocate(rods(1)%strains(6, ns, n_stored - 1), source=0.0_rk)
        call expect_short('strains')
        rods(1) = synthetic_rod(1)
        deallocate(rods(1)%branch_stress)
        allocate(rods(1)%branch_stress(6, ns, 2, n_stored - 1), source=0.0_rk)
        call expect_short('branch_stress')
        rods(1) = synthetic_rod(1)
        rods(1)%dissipated = rods(1)%dissipated(1:n_stored - 1)
        call expect_short('dissipated')
        rods(1) = synthetic_rod(1)
        deallocate(rods(1)%tie_force)
        allocate(rods(1)%tie_force(3, 2, n_stored - 1), source=0.0_rk)
        call expect_short('tie_force')
        inquire(file=path, exist=exists)
        CHECK_TRUE(.not. exists, 'no file for a short history')
    contains
        subroutine expect_short(what)
            character(len=*), intent(in) :: what
            if (allocated(err)) deallocate(err)
            call write_result_file(path, synthetic_meta(), rods, err)
            CHECK_TRUE(allocated(err), 'a short array is an error: ' // what)
            if (allocated(err)) then
                CHECK_CONTAINS(err%message, 'rod "arm" is inconsistent: ' // what // ' holds', what)
            end if
        end subroutine expect_short
    end subroutine test_short_history

    !> The HDF5 layer directly: attributes of every kind (replaced when written again), a
    !> contiguous rank-2 dataset, an empty string dataset, and the errors for an existing name
    !> and a closed file. check_result_file.py checks the values.
    subroutine test_hdf5_layer()
        type(hdf5_file_t) :: file
        type(error_t), allocatable :: err
        real(rk) :: matrix(2, 3)
        integer :: i
        matrix = reshape([(real(i, rk), i = 1, 6)], [2, 3])
        call file%create(layer_path, err)
        CHECK_TRUE(.not. allocated(err), 'create')
        if (allocated(err)) return
        call file%create_group('/a/b/c', err)
        CHECK_TRUE(.not. allocated(err), 'nested groups')
        call file%create_group('/a/b', err)
        CHECK_TRUE(.not. allocated(err), 'an existing group is fine')
        call file%write_dataset('/a/matrix', matrix, 'kg', 'a 2 x 3 matrix', err)
        CHECK_TRUE(.not. allocated(err), 'rank-2 dataset')
        call file%write_attribute('/a/matrix', 'count', 42, err)
        call file%write_attribute('/a/matrix', 'count', 7, err)
        CHECK_TRUE(.not. allocated(err), 'attribute replaced')
        call file%write_attribute('/a/b', 'scale', 2.5_rk, err)
        call file%write_attribute('/a/b', 'vector', [1.0_rk, 2.0_rk, 3.0_rk], err)
        call file%write_attribute('/', 'label', 'root label', err)
        CHECK_TRUE(.not. allocated(err), 'attributes of each kind')
        call file%write_string_dataset('/a/empty_text', '', 'an empty text', err)
        CHECK_TRUE(.not. allocated(err), 'empty string dataset')
        call file%write_dataset('/a/matrix', matrix, 'kg', 'again', err)
        CHECK_TRUE(allocated(err), 'an existing name is an error')
        if (allocated(err)) then
            CHECK_CONTAINS(err%message, '"/a/matrix"', 'names the object')
            CHECK_CONTAINS(err%message, layer_path, 'names the file')
        end if
        call file%write_attribute('/no/such/object', 'x', 1, err)
        CHECK_TRUE(allocated(err), 'attribute of a missing object')
        if (allocated(err)) then
            CHECK_CONTAINS(err%message, 'H5Oopen failed for "/no/such/object"', 'call, object')
        end if
        call file%close(err)
        CHECK_TRUE(.not. allocated(err), 'close')
        CHECK_TRUE(.not. file%is_open(), 'closed')
        call file%write_attribute('/', 'late', 1, err)
        CHECK_TRUE(allocated(err), 'writing to a closed file is an error')
    end subroutine test_hdf5_layer

    !> Datasets stay open between calls (hdf5_file_t%open_sets): a series grown and written
    !> record by record reads back whole, a deleted series re-created under the same name with
    !> another record shape is the new one (not the kept handle of the old), and everything is
    !> in the file after close.
    subroutine test_hdf5_kept_datasets()
        type(hdf5_file_t) :: file
        type(error_t), allocatable :: err
        real(rk), allocatable :: values(:)
        integer, allocatable :: dims(:)
        integer :: k
        call file%create(kept_path, err)
        if (.not. allocated(err)) call file%create_series('/s/x', [2], .false., 'm', 'x', err)
        do k = 1, 3
            if (.not. allocated(err)) call file%set_records('/s/x', k, err)
            if (.not. allocated(err)) call file%write_records('/s/x', k, [real(k, rk), -real(k, rk)], err)
        end do
        if (.not. allocated(err)) call file%read('/s/x', values, err)
        CHECK_TRUE(.not. allocated(err), 'grown, written and read')
        if (allocated(err)) return
        CHECK_TRUE(all(values == [1.0_rk, -1.0_rk, 2.0_rk, -2.0_rk, 3.0_rk, -3.0_rk]), 'records in order')
        call file%delete('/s/x', err)
        if (.not. allocated(err)) call file%create_series('/s/x', [3], .false., 'm', 'x', err)
        if (.not. allocated(err)) call file%set_records('/s/x', 1, err)
        if (.not. allocated(err)) call file%write_records('/s/x', 1, [4.0_rk, 5.0_rk, 6.0_rk], err)
        if (.not. allocated(err)) call file%dataset_dims('/s/x', dims, err)
        CHECK_TRUE(.not. allocated(err), 're-created after delete')
        if (allocated(err)) return
        CHECK_TRUE(all(dims == [3, 1]), 'the re-created shape, not the deleted one')
        call file%close(err)
        CHECK_TRUE(.not. allocated(err), 'close with kept datasets')
        call file%open(kept_path, err, writable=.false.)
        if (.not. allocated(err)) call file%read('/s/x', values, err)
        CHECK_TRUE(.not. allocated(err), 'reopened and read')
        if (allocated(err)) return
        CHECK_TRUE(all(values == [4.0_rk, 5.0_rk, 6.0_rk]), 'the values after close')
        call file%close(err)
        CHECK_TRUE(.not. allocated(err), 'closed again')
    end subroutine test_hdf5_kept_datasets

    !> The bundle series of a rod that has them (arm) follow `&output fields`: 'contact'
    !> selects series/contact/{energy,force,penetration}, 'ties' series/ties/force, 'all' both;
    !> a rod without them (tail) has neither under any selection. Shapes are checked in
    !> Fortran order ([3, 2, steps] is h5py's (steps, 2, 3)); check_result_file.py checks the
    !> values of the file test_two_rods wrote.
    subroutine test_bundle_series_selection()
        type(rod_history_t) :: rods(2)
        character(len=*), parameter :: contact(3) = [character(len=26) :: &
            'series/contact/energy', 'series/contact/force', 'series/contact/penetration']
        character(len=*), parameter :: ties = 'series/ties/force'
        !> The selection under test, for the messages.
        character(len=:), allocatable :: what
        rods(1) = synthetic_rod(1)
        rods(2) = synthetic_rod(2)
        CHECK_EQUAL(unknown_fields('position, contact,ties'), '', 'contact and ties selectable')
        CHECK_EQUAL(unknown_fields('contacts'), "'contacts'", 'a misspelling is unknown')
        call write_selected('all', .true., .true.)
        call write_selected('position,ties', .false., .true.)
        call write_selected('contact, stress', .true., .false.)
        call write_selected('position', .false., .false.)
    contains
        !> Write both rods with `selection`; expect the arm's contact and tie datasets as told.
        subroutine write_selected(selection, with_contact, with_ties)
            character(len=*), intent(in) :: selection
            logical, intent(in) :: with_contact, with_ties
            type(rod_layout_t) :: layouts(2)
            type(result_writer_t) :: writer
            type(hdf5_file_t) :: file
            type(error_t), allocatable :: err
            integer :: i
            what = ' (fields ''' // selection // ''')'
            do i = 1, 2
                layouts(i) = layout_of(rods(i), 0, 0)
            end do
            CHECK_TRUE(index(layouts(1)%recorded, ',' // ties // ',') > 0, 'arm records ties')
            CHECK_TRUE(index(layouts(2)%recorded, 'contact') == 0, 'tail records no contact')
            CHECK_TRUE(index(layouts(2)%recorded, 'ties') == 0, 'tail records no ties')
            call prepare_result_file(selection_path, synthetic_meta(), layouts, selection, err)
            if (.not. allocated(err)) call writer%open(selection_path, layouts, selection, &
                [0, 0], .false., err)
            if (.not. allocated(err)) call writer%extend([n_stored, n_stored], err)
            do i = 1, 2
                if (.not. allocated(err)) call writer%write_records(i, err, rods(i))
            end do
            if (.not. allocated(err)) call writer%close(err)
            CHECK_TRUE(.not. allocated(err), 'written' // what)
            if (allocated(err)) then
                print '(a)', err%describe()
                return
            end if
            call file%open(selection_path, err, writable=.false.)
            CHECK_TRUE(.not. allocated(err), 'reopened' // what)
            if (allocated(err)) return
            call expect_dims(file, '/rods/arm/' // trim(contact(1)), with_contact, [n_stored])
            call expect_dims(file, '/rods/arm/' // trim(contact(2)), with_contact, [3, n_stored])
            call expect_dims(file, '/rods/arm/' // trim(contact(3)), with_contact, [n_stored])
            call expect_dims(file, '/rods/arm/' // ties, with_ties, [3, 2, n_stored])
            CHECK_TRUE(file%exists('/rods/arm/series/dt'), 'other series stay' // what)
            CHECK_TRUE(.not. file%exists('/rods/tail/series/contact'), 'tail: no contact' // what)
            CHECK_TRUE(.not. file%exists('/rods/tail/series/ties'), 'tail: no ties' // what)
            call file%close(err)
        end subroutine write_selected

        subroutine expect_dims(file, path, present_, dims)
            type(hdf5_file_t), intent(inout) :: file
            character(len=*), intent(in) :: path
            logical, intent(in) :: present_
            integer, intent(in) :: dims(:)
            type(error_t), allocatable :: err
            integer, allocatable :: actual(:)
            CHECK_EQUAL(file%exists(path), present_, path // ' present or absent' // what)
            if (.not. (present_ .and. file%exists(path))) return
            call file%dataset_dims(path, actual, err)
            CHECK_TRUE(.not. allocated(err), path // ' dims read' // what)
            if (allocated(err)) return
            CHECK_EQUAL(size(actual), size(dims), path // ' rank' // what)
            if (size(actual) /= size(dims)) return
            CHECK_TRUE(all(actual == dims), path // ' shape' // what)
        end subroutine expect_dims
    end subroutine test_bundle_series_selection

end module rs_test_io_result_file

!> Test program: runs the tests of rs_test_io_result_file; exits non-zero if any failed.
program test_result_file
    use rs_test_io_result_file, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_result_file
