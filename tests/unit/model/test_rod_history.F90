#include "rs_assert.h"
!> Unit tests of rs_model_rod_history: `init` sizes and zero-fills every array (the Maxwell
!> branch stresses only with n_branches > 0), `free` deallocates, `next_record` hands out
!> 1 .. capacity and then 0, re-`init` starts over, and `pack` followed by `unpack` reproduces
!> every stored field bit for bit (filled with distinct pseudo-random values, a different range
!> per field so that a swapped field is caught), with and without branches, the name and
!> formulation strings, and only the first n_stored records: the records beyond n_stored do not
!> change what `pack` produces.
module rs_test_model_rod_history
    use rs_core_kinds, only: rk
    use rs_test_assert, only: run_test, assert_true, assert_close, assert_equal
    use rs_test_random, only: set_random_seed
    use rs_model_rod_history, only: rod_history_t
    implicit none
    private

    public :: run_all_tests

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call set_random_seed(2417, 31)
        call run_test('init_sizes', test_init_sizes)
        call run_test('init_sizes_branches', test_init_sizes_branches)
        call run_test('next_record_capacity', test_next_record_capacity)
        call run_test('reinit_starts_over', test_reinit_starts_over)
        call run_test('pack_unpack_round_trip', test_pack_unpack_round_trip)
        call run_test('pack_unpack_round_trip_branches', test_pack_unpack_round_trip_branches)
        call run_test('pack_sizes_only_stored_records', test_pack_sizes_only_stored_records)
        call run_test('pack_sizes_branches', test_pack_sizes_branches)
        call run_test('unstored_records_not_packed', test_unstored_records_not_packed)
        call run_test('round_trip_no_records', test_round_trip_no_records)
        call run_test('unpack_into_used_history', test_unpack_into_used_history)
    end subroutine run_all_tests

    subroutine test_init_sizes()
        type(rod_history_t) :: h
        call h%init('beam', 'ph_director', 7, 12, 5)
        CHECK_EQUAL(h%name, 'beam', 'name')
        CHECK_EQUAL(h%formulation, 'ph_director', 'formulation')
        CHECK_EQUAL(h%n_nodes, 7, 'n_nodes')
        CHECK_EQUAL(h%n_stress_points, 12, 'n_stress_points')
        CHECK_EQUAL(h%n_branches, 0, 'no Maxwell branches by default')
        CHECK_EQUAL(h%n_stored, 0, 'nothing stored yet')
        CHECK_EQUAL(size(h%mesh), 7, 'mesh')
        CHECK_EQUAL(size(h%stress_mesh), 12, 'stress_mesh')
        CHECK_EQUAL(size(h%time), 5, 'time')
        CHECK_TRUE(all(shape(h%position) == [3, 7, 5]), 'position shape')
        CHECK_TRUE(all(shape(h%directors) == [3, 3, 7, 5]), 'directors shape')
        CHECK_TRUE(all(shape(h%velocity) == [3, 7, 5]), 'velocity shape')
        CHECK_TRUE(all(shape(h%director_velocity) == [3, 3, 7, 5]), 'director_velocity shape')
        CHECK_TRUE(all(shape(h%stress) == [6, 12, 5]), 'stress shape')
        CHECK_TRUE(all(shape(h%strains) == [6, 12, 5]), 'strains shape')
        CHECK_TRUE(.not. allocated(h%branch_stress), 'no branch_stress without branches')
        CHECK_TRUE(all(shape(h%linear_momentum) == [3, 5]), 'linear_momentum shape')
        CHECK_TRUE(all(shape(h%angular_momentum) == [3, 5]), 'angular_momentum shape')
        CHECK_TRUE(all(shape(h%center_of_mass) == [3, 5]), 'center_of_mass shape')
        CHECK_EQUAL(size(h%kinetic), 5, 'kinetic')
        CHECK_EQUAL(size(h%strain), 5, 'strain')
        CHECK_EQUAL(size(h%total), 5, 'total')
        CHECK_EQUAL(size(h%external_work), 5, 'external_work')
        CHECK_EQUAL(size(h%balance_error), 5, 'balance_error')
        CHECK_EQUAL(size(h%dissipated), 5, 'dissipated')
        CHECK_EQUAL(size(h%actuator_work), 5, 'actuator_work')
        CHECK_EQUAL(size(h%constraint_residual), 5, 'constraint_residual')
        CHECK_EQUAL(size(h%newton_iterations), 5, 'newton_iterations')
        CHECK_EQUAL(size(h%newton_residual), 5, 'newton_residual')
        CHECK_EQUAL(size(h%dt), 5, 'dt')
        CHECK_TRUE(all(h%position == 0.0_rk) .and. all(h%directors == 0.0_rk), 'zero-filled')
        CHECK_TRUE(all(h%stress == 0.0_rk) .and. all(h%newton_iterations == 0), 'zero-filled')
        CHECK_TRUE(all(h%strains == 0.0_rk) .and. all(h%dissipated == 0.0_rk), 'zero-filled')
        CHECK_TRUE(all(h%actuator_work == 0.0_rk), 'zero-filled')
        call h%free()
        CHECK_TRUE(.not. allocated(h%position) .and. .not. allocated(h%name), 'free deallocates')
        CHECK_TRUE(.not. allocated(h%strains), 'free deallocates strains')
        CHECK_TRUE(.not. allocated(h%dissipated), 'free deallocates dissipated')
        CHECK_TRUE(.not. allocated(h%actuator_work), 'free deallocates actuator_work')
        CHECK_EQUAL(h%n_nodes, 0, 'free resets n_nodes')
    end subroutine test_init_sizes

    ! With Maxwell branches: branch_stress (6, points, branches, capacity), zero-filled; `free`
    ! and a re-`init` without branches drop it.
    subroutine test_init_sizes_branches()
        type(rod_history_t) :: h
        call h%init('damped', 'ph_director', 4, 6, 3, n_branches=2)
        CHECK_EQUAL(h%n_branches, 2, 'n_branches')
        CHECK_TRUE(allocated(h%branch_stress), 'branch_stress allocated')
        if (.not. allocated(h%branch_stress)) return
        CHECK_TRUE(all(shape(h%branch_stress) == [6, 6, 2, 3]), 'branch_stress shape')
        CHECK_TRUE(all(h%branch_stress == 0.0_rk), 'branch_stress zero-filled')
        CHECK_TRUE(all(shape(h%strains) == [6, 6, 3]), 'strains shape')
        call h%free()
        CHECK_EQUAL(h%n_branches, 0, 'free resets n_branches')
        CHECK_TRUE(.not. allocated(h%branch_stress), 'free deallocates branch_stress')
        call h%init('damped', 'ph_director', 4, 6, 3, 1)
        CHECK_TRUE(all(shape(h%branch_stress) == [6, 6, 1, 3]), 'positional n_branches')
        call h%init('elastic', 'ph_director', 4, 6, 3)
        CHECK_EQUAL(h%n_branches, 0, 're-init without branches')
        CHECK_TRUE(.not. allocated(h%branch_stress), 're-init without branches drops them')
        call h%init('elastic', 'ph_director', 4, 6, 3, 0)
        CHECK_TRUE(.not. allocated(h%branch_stress), 'n_branches = 0: no branch_stress')
    end subroutine test_init_sizes_branches

    subroutine test_next_record_capacity()
        type(rod_history_t) :: h
        integer :: k
        call h%init('r', 'ph_director', 2, 1, 3)
        do k = 1, 3
            CHECK_EQUAL(h%next_record(), k, 'records 1 .. capacity in order')
            CHECK_EQUAL(h%n_stored, k, 'n_stored counts them')
        end do
        CHECK_EQUAL(h%next_record(), 0, 'full: 0')
        CHECK_EQUAL(h%next_record(), 0, 'still full: 0')
        CHECK_EQUAL(h%n_stored, 3, 'n_stored stays at the capacity')
        call h%init('r', 'ph_director', 2, 1, 0)
        CHECK_EQUAL(h%next_record(), 0, 'capacity 0: full at once')
        CHECK_EQUAL(h%n_stored, 0, 'capacity 0: nothing stored')
    end subroutine test_next_record_capacity

    subroutine test_reinit_starts_over()
        type(rod_history_t) :: h
        integer :: k
        call h%init('first', 'ph_director', 3, 2, 2)
        do k = 1, 2
            CHECK_EQUAL(h%next_record(), k, 'first life')
        end do
        h%position = 5.0_rk
        call h%init('second rod', 'se3_pg', 4, 1, 4)
        CHECK_EQUAL(h%n_stored, 0, 're-init empties')
        CHECK_EQUAL(h%name, 'second rod', 'new name')
        CHECK_EQUAL(h%formulation, 'se3_pg', 'new formulation')
        CHECK_TRUE(all(shape(h%position) == [3, 4, 4]), 'new shape')
        CHECK_TRUE(all(h%position == 0.0_rk), 'new values are zero')
        CHECK_EQUAL(h%next_record(), 1, 'records start at 1 again')
    end subroutine test_reinit_starts_over

    !> Fill every array of `h` (all records, stored or not) with pseudo-random values, field k
    !> in [10 k, 10 k + 1) so that no two fields share a value range.
    subroutine fill_random(h)
        type(rod_history_t), intent(inout) :: h
        integer :: k
        real(rk), allocatable :: r(:)
        k = 0
        call random_number(h%mesh)
        call shift(h%mesh)
        call random_number(h%stress_mesh)
        call shift(h%stress_mesh)
        call random_number(h%time)
        call shift(h%time)
        call random_number(h%position)
        h%position = h%position + next_offset()
        call random_number(h%directors)
        h%directors = h%directors + next_offset()
        call random_number(h%velocity)
        h%velocity = h%velocity + next_offset()
        call random_number(h%director_velocity)
        h%director_velocity = h%director_velocity + next_offset()
        call random_number(h%stress)
        h%stress = h%stress + next_offset()
        call random_number(h%strains)
        h%strains = h%strains + next_offset()
        if (allocated(h%branch_stress)) then
            call random_number(h%branch_stress)
            h%branch_stress = h%branch_stress + next_offset()
        end if
        call random_number(h%kinetic)
        call shift(h%kinetic)
        call random_number(h%strain)
        call shift(h%strain)
        call random_number(h%total)
        call shift(h%total)
        call random_number(h%external_work)
        call shift(h%external_work)
        call random_number(h%balance_error)
        call shift(h%balance_error)
        call random_number(h%dissipated)
        call shift(h%dissipated)
        call random_number(h%actuator_work)
        call shift(h%actuator_work)
        call random_number(h%linear_momentum)
        h%linear_momentum = h%linear_momentum + next_offset()
        call random_number(h%angular_momentum)
        h%angular_momentum = h%angular_momentum + next_offset()
        call random_number(h%center_of_mass)
        h%center_of_mass = h%center_of_mass + next_offset()
        call random_number(h%constraint_residual)
        call shift(h%constraint_residual)
        call random_number(h%newton_residual)
        call shift(h%newton_residual)
        call random_number(h%dt)
        call shift(h%dt)
        allocate(r(size(h%newton_iterations)))
        call random_number(r)
        h%newton_iterations = 1 + int(1000.0_rk * r)
    contains
        subroutine shift(v)
            real(rk), intent(inout) :: v(:)
            v = v + next_offset()
        end subroutine shift
        real(rk) function next_offset()
            k = k + 1
            next_offset = 10.0_rk * real(k, rk)
        end function next_offset
    end subroutine fill_random

    !> A history named `name` with `n_stored` of `capacity` records in use and `n_branches`
    !> Maxwell branches (default 0), filled at random.
    subroutine random_history(h, name, formulation, n_nodes, n_stress_points, capacity, n_stored, &
            n_branches)
        type(rod_history_t), intent(out) :: h
        character(len=*), intent(in) :: name, formulation
        integer, intent(in) :: n_nodes, n_stress_points, capacity, n_stored
        integer, intent(in), optional :: n_branches
        integer :: k
        call h%init(name, formulation, n_nodes, n_stress_points, capacity, n_branches)
        call fill_random(h)
        do k = 1, n_stored
            if (h%next_record() /= k) error stop 'random_history: next_record'
        end do
    end subroutine random_history

    !> Every field of `b` equals that of `a` exactly in the first a%n_stored records.
    subroutine check_same_records(a, b)
        type(rod_history_t), intent(in) :: a, b
        integer :: n
        n = a%n_stored
        CHECK_EQUAL(b%n_stored, n, 'n_stored')
        CHECK_EQUAL(b%n_nodes, a%n_nodes, 'n_nodes')
        CHECK_EQUAL(b%n_stress_points, a%n_stress_points, 'n_stress_points')
        CHECK_EQUAL(b%n_branches, a%n_branches, 'n_branches')
        CHECK_TRUE(allocated(b%branch_stress) .eqv. allocated(a%branch_stress), 'branch_stress')
        CHECK_EQUAL(len(b%name), len(a%name), 'length of the name')
        CHECK_EQUAL(b%name, a%name, 'name')
        CHECK_EQUAL(len(b%formulation), len(a%formulation), 'length of the formulation')
        CHECK_EQUAL(b%formulation, a%formulation, 'formulation')
        CHECK_TRUE(size(b%time) >= n, 'room for the records')
        if (b%n_stored /= n .or. size(b%time) < n) return
        CHECK_CLOSE(b%mesh, a%mesh, 0.0_rk, 0.0_rk, 'mesh')
        CHECK_CLOSE(b%stress_mesh, a%stress_mesh, 0.0_rk, 0.0_rk, 'stress_mesh')
        CHECK_CLOSE(b%time(1:n), a%time(1:n), 0.0_rk, 0.0_rk, 'time')
        CHECK_CLOSE(flat3(b%position, n), flat3(a%position, n), 0.0_rk, 0.0_rk, 'position')
        CHECK_CLOSE(flat4(b%directors, n), flat4(a%directors, n), 0.0_rk, 0.0_rk, 'directors')
        CHECK_CLOSE(flat3(b%velocity, n), flat3(a%velocity, n), 0.0_rk, 0.0_rk, 'velocity')
        CHECK_CLOSE(flat4(b%director_velocity, n), flat4(a%director_velocity, n), 0.0_rk, 0.0_rk, 'director_velocity')
        CHECK_CLOSE(flat3(b%stress, n), flat3(a%stress, n), 0.0_rk, 0.0_rk, 'stress')
        CHECK_CLOSE(flat3(b%strains, n), flat3(a%strains, n), 0.0_rk, 0.0_rk, 'strains')
        if (allocated(a%branch_stress) .and. allocated(b%branch_stress)) then
            CHECK_TRUE(all(shape(b%branch_stress(:, :, :, 1:n)) == shape(a%branch_stress(:, :, :, 1:n))), 'shape')
            CHECK_CLOSE(flat4(b%branch_stress, n), flat4(a%branch_stress, n), 0.0_rk, 0.0_rk, 'branch_stress')
        end if
        CHECK_CLOSE(b%kinetic(1:n), a%kinetic(1:n), 0.0_rk, 0.0_rk, 'kinetic')
        CHECK_CLOSE(b%strain(1:n), a%strain(1:n), 0.0_rk, 0.0_rk, 'strain')
        CHECK_CLOSE(b%total(1:n), a%total(1:n), 0.0_rk, 0.0_rk, 'total')
        CHECK_CLOSE(b%external_work(1:n), a%external_work(1:n), 0.0_rk, 0.0_rk, 'external_work')
        CHECK_CLOSE(b%balance_error(1:n), a%balance_error(1:n), 0.0_rk, 0.0_rk, 'balance_error')
        CHECK_CLOSE(b%dissipated(1:n), a%dissipated(1:n), 0.0_rk, 0.0_rk, 'dissipated')
        CHECK_CLOSE(b%actuator_work(1:n), a%actuator_work(1:n), 0.0_rk, 0.0_rk, 'actuator_work')
        CHECK_CLOSE(b%linear_momentum(:, 1:n), a%linear_momentum(:, 1:n), 0.0_rk, 0.0_rk, 'linear_momentum')
        CHECK_CLOSE(b%angular_momentum(:, 1:n), a%angular_momentum(:, 1:n), 0.0_rk, 0.0_rk, 'angular_momentum')
        CHECK_CLOSE(b%center_of_mass(:, 1:n), a%center_of_mass(:, 1:n), 0.0_rk, 0.0_rk, 'center_of_mass')
        CHECK_CLOSE(b%constraint_residual(1:n), a%constraint_residual(1:n), 0.0_rk, 0.0_rk, 'constraint_residual')
        CHECK_CLOSE(b%newton_residual(1:n), a%newton_residual(1:n), 0.0_rk, 0.0_rk, 'newton_residual')
        CHECK_CLOSE(b%dt(1:n), a%dt(1:n), 0.0_rk, 0.0_rk, 'dt')
        CHECK_TRUE(all(b%newton_iterations(1:n) == a%newton_iterations(1:n)), 'newton_iterations')
    end subroutine check_same_records

    !> The first n records of a per-node field as one vector.
    pure function flat3(field, n) result(v)
        real(rk), intent(in) :: field(:, :, :)
        integer, intent(in) :: n
        real(rk), allocatable :: v(:)
        v = pack(field(:, :, 1:n), .true.)
    end function flat3

    !> The first n records of a per-node director field as one vector.
    pure function flat4(field, n) result(v)
        real(rk), intent(in) :: field(:, :, :, :)
        integer, intent(in) :: n
        real(rk), allocatable :: v(:)
        v = pack(field(:, :, :, 1:n), .true.)
    end function flat4

    ! 4 of 6 records stored; a name with blanks, a bar and trailing blanks survives as it is.
    subroutine test_pack_unpack_round_trip()
        type(rod_history_t) :: a, b
        integer, allocatable :: header(:)
        real(rk), allocatable :: values(:)
        call random_history(a, 'left arm|2  ', 'ph_director', 5, 8, 6, 4)
        call a%pack(header, values)
        call b%unpack(header, values)
        call check_same_records(a, b)
        ! The values are distinct: a field read from the wrong place would not match.
        CHECK_TRUE(a%kinetic(1) /= a%strain(1), 'distinct fields')
        CHECK_TRUE(a%position(1, 1, 1) /= a%velocity(1, 1, 1), 'distinct fields')
        CHECK_TRUE(a%stress(1, 1, 1) /= a%strains(1, 1, 1), 'distinct fields')
        CHECK_TRUE(a%dissipated(1) /= a%actuator_work(1), 'distinct fields')
    end subroutine test_pack_unpack_round_trip

    ! 3 branches, 5 of 7 records stored.
    subroutine test_pack_unpack_round_trip_branches()
        type(rod_history_t) :: a, b
        integer, allocatable :: header(:)
        real(rk), allocatable :: values(:)
        call random_history(a, 'damped arm', 'ph_director', 4, 6, 7, 5, n_branches=3)
        call a%pack(header, values)
        call b%unpack(header, values)
        call check_same_records(a, b)
        CHECK_TRUE(allocated(b%branch_stress), 'branch_stress unpacked')
        if (.not. allocated(b%branch_stress)) return
        CHECK_TRUE(all(shape(b%branch_stress) == [6, 6, 3, 5]), 'branch_stress shape')
        CHECK_TRUE(a%branch_stress(1, 1, 1, 1) /= a%stress(1, 1, 1), 'distinct fields')
        CHECK_TRUE(a%branch_stress(1, 1, 1, 1) /= a%branch_stress(1, 1, 2, 1), 'distinct branches')
    end subroutine test_pack_unpack_round_trip_branches

    ! header: n_nodes, n_stress_points, n_stored, the two string lengths, n_branches, the
    ! iterations of the stored records and one code per character; values: the meshes and, per
    ! stored record, time, 3 + 9 + 3 + 9 numbers per node, 6 + 6 per stress point (stress,
    ! strains) and 7 + 3 * 3 + 3 scalars.
    subroutine test_pack_sizes_only_stored_records()
        type(rod_history_t) :: a
        integer, allocatable :: header(:)
        real(rk), allocatable :: values(:)
        integer, parameter :: nn = 3, ns = 4, n = 2
        call random_history(a, 'rod', 'ph_director', nn, ns, 5, n)
        call a%pack(header, values)
        CHECK_EQUAL(size(header), 6 + n + 3 + 11, 'header size')
        CHECK_EQUAL(size(values), nn + ns + n * (1 + 24 * nn + 12 * ns + 19), 'values size')
        CHECK_EQUAL(header(1), nn, 'header: n_nodes')
        CHECK_EQUAL(header(2), ns, 'header: n_stress_points')
        CHECK_EQUAL(header(3), n, 'header: n_stored')
        CHECK_EQUAL(header(6), 0, 'header: n_branches')
    end subroutine test_pack_sizes_only_stored_records

    ! With nb branches each stored record adds 6 numbers per stress point and branch.
    subroutine test_pack_sizes_branches()
        type(rod_history_t) :: a
        integer, allocatable :: header(:)
        real(rk), allocatable :: values(:)
        integer, parameter :: nn = 3, ns = 4, n = 2, nb = 2
        call random_history(a, 'rod', 'ph_director', nn, ns, 5, n, nb)
        call a%pack(header, values)
        CHECK_EQUAL(size(header), 6 + n + 3 + 11, 'header size')
        CHECK_EQUAL(size(values), nn + ns + n * (1 + 24 * nn + (12 + 6 * nb) * ns + 19), 'values')
        CHECK_EQUAL(header(6), nb, 'header: n_branches')
    end subroutine test_pack_sizes_branches

    ! Two histories that differ only beyond n_stored pack to the same arrays.
    subroutine test_unstored_records_not_packed()
        type(rod_history_t) :: a
        integer, allocatable :: header1(:), header2(:)
        real(rk), allocatable :: values1(:), values2(:)
        call random_history(a, 'beam', 'ph_director', 4, 3, 5, 3, n_branches=2)
        call a%pack(header1, values1)
        a%time(4:) = -1.0_rk
        a%strains(:, :, 4:) = -8.0_rk
        a%branch_stress(:, :, :, 4:) = -9.0_rk
        a%dissipated(4:) = -10.0_rk
        a%actuator_work(4:) = -11.0_rk
        a%position(:, :, 4:) = -2.0_rk
        a%directors(:, :, :, 4:) = -3.0_rk
        a%stress(:, :, 4:) = -4.0_rk
        a%dt(4:) = -5.0_rk
        a%newton_iterations(4:) = -6
        a%center_of_mass(:, 4:) = -7.0_rk
        call a%pack(header2, values2)
        CHECK_EQUAL(size(header2), size(header1), 'same header size')
        CHECK_EQUAL(size(values2), size(values1), 'same values size')
        if (size(header2) /= size(header1) .or. size(values2) /= size(values1)) return
        CHECK_TRUE(all(header2 == header1), 'same header')
        CHECK_CLOSE(values2, values1, 0.0_rk, 0.0_rk, 'same values')
    end subroutine test_unstored_records_not_packed

    ! No record stored, empty name: the meshes and the strings still come back.
    subroutine test_round_trip_no_records()
        type(rod_history_t) :: a, b
        integer, allocatable :: header(:)
        real(rk), allocatable :: values(:)
        call random_history(a, '', 'ph_director', 3, 2, 4, 0)
        call a%pack(header, values)
        CHECK_EQUAL(size(values), 3 + 2, 'only the meshes')
        call b%unpack(header, values)
        call check_same_records(a, b)
        CHECK_EQUAL(b%next_record(), 1, 'the unpacked history can take a record')
    end subroutine test_round_trip_no_records

    ! Unpacking into a history that already holds another rod replaces it entirely.
    subroutine test_unpack_into_used_history()
        type(rod_history_t) :: a, b
        integer, allocatable :: header(:)
        real(rk), allocatable :: values(:)
        call random_history(b, 'old rod with a long name', 'se3_strand', 11, 20, 9, 9, 4)
        call random_history(a, 'new', 'ph_director', 2, 3, 7, 7)
        call a%pack(header, values)
        call b%unpack(header, values)
        call check_same_records(a, b)
        CHECK_TRUE(all(shape(b%position) == [3, 2, 7]), 'new shape')
        CHECK_TRUE(.not. allocated(b%branch_stress), 'the old branches are gone')
        ! And the other way: branches into a history without them.
        call random_history(a, 'new damped', 'ph_director', 2, 3, 7, 6, 2)
        call a%pack(header, values)
        call b%unpack(header, values)
        call check_same_records(a, b)
    end subroutine test_unpack_into_used_history

end module rs_test_model_rod_history

!> Test program: runs the tests of rs_test_model_rod_history; exits non-zero if any failed.
program test_rod_history
    use rs_test_model_rod_history, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_rod_history
