#include "rs_assert.h"
!> Unit tests of rs_parallel_metis (partition_graph): a path of 8 vertices in 2 parts is cut
!> once into two contiguous halves of 4; two 4-cliques joined by one edge are separated at
!> that edge; vertex weights are balanced; a 4 x 4 grid in 4 parts gets 4 vertices each; one
!> part (and a single vertex) is answered without METIS; inconsistent sizes are errors; the
!> METIS version is 5.1.x (DESIGN.md 5). METIS needs no MPI initialization.
module rs_test_parallel_metis
    use, intrinsic :: iso_c_binding, only: c_int32_t
    use rs_core_error, only: error_t
    use rs_test_assert, only: run_test, assert_true, assert_equal, assert_contains
    use rs_parallel_metis, only: partition_graph, metis_version
    implicit none
    private

    public :: run_all_tests

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('path_of_8_in_2_parts', test_path_of_8_in_2_parts)
        call run_test('two_cliques', test_two_cliques)
        call run_test('vertex_weights_balanced', test_vertex_weights_balanced)
        call run_test('grid_in_4_parts', test_grid_in_4_parts)
        call run_test('one_part_without_metis', test_one_part_without_metis)
        call run_test('inconsistent_sizes', test_inconsistent_sizes)
        call run_test('version', test_version)
    end subroutine run_all_tests

    !> 0-based CSR arrays of the undirected graph with `n` vertices and 1-based edges (a(k), b(k)).
    subroutine csr_from_edges(n, a, b, xadj, adjncy)
        integer, intent(in) :: n, a(:), b(:)
        integer(c_int32_t), allocatable, intent(out) :: xadj(:), adjncy(:)
        integer :: degree(n), fill(n), k, v
        degree = 0
        do k = 1, size(a)
            degree(a(k)) = degree(a(k)) + 1
            degree(b(k)) = degree(b(k)) + 1
        end do
        allocate(xadj(n + 1), adjncy(2 * size(a)))
        xadj(1) = 0
        do v = 1, n
            xadj(v + 1) = xadj(v) + degree(v)
        end do
        fill = 0
        do k = 1, size(a)
            adjncy(xadj(a(k)) + fill(a(k)) + 1) = b(k) - 1
            fill(a(k)) = fill(a(k)) + 1
            adjncy(xadj(b(k)) + fill(b(k)) + 1) = a(k) - 1
            fill(b(k)) = fill(b(k)) + 1
        end do
    end subroutine csr_from_edges

    !> Number of edges whose ends lie in different parts.
    integer function edge_cut(a, b, part) result(cut)
        integer, intent(in) :: a(:), b(:)
        integer(c_int32_t), intent(in) :: part(:)
        integer :: k
        cut = 0
        do k = 1, size(a)
            if (part(a(k)) /= part(b(k))) cut = cut + 1
        end do
    end function edge_cut

    subroutine test_path_of_8_in_2_parts()
        integer, parameter :: n = 8
        integer :: a(n - 1), b(n - 1), k
        integer(c_int32_t), allocatable :: xadj(:), adjncy(:)
        integer(c_int32_t) :: weights(n), part(n)
        type(error_t), allocatable :: err
        a = [(k, k = 1, n - 1)]
        b = a + 1
        call csr_from_edges(n, a, b, xadj, adjncy)
        weights = 1
        part = -1
        call partition_graph(xadj, adjncy, weights, 2, part, err)
        CHECK_TRUE(.not. allocated(err), 'no error')
        CHECK_TRUE(all(part == 0 .or. part == 1), 'parts are 0 and 1')
        CHECK_EQUAL(count(part == 0), 4, 'part 0 has 4 vertices')
        CHECK_EQUAL(count(part == 1), 4, 'part 1 has 4 vertices')
        CHECK_EQUAL(edge_cut(a, b, part), 1, 'one cut edge')
        ! Contiguous: along the path the part changes once, so each part is one run.
        CHECK_EQUAL(count(part(2:n) /= part(1:n - 1)), 1, 'each part contiguous')
    end subroutine test_path_of_8_in_2_parts

    ! Two 4-cliques {1..4} and {5..8} joined by the edge 4-5: the minimum balanced cut is that
    ! edge.
    subroutine test_two_cliques()
        integer, parameter :: a(13) = [1, 1, 1, 2, 2, 3, 5, 5, 5, 6, 6, 7, 4]
        integer, parameter :: b(13) = [2, 3, 4, 3, 4, 4, 6, 7, 8, 7, 8, 8, 5]
        integer(c_int32_t), allocatable :: xadj(:), adjncy(:)
        integer(c_int32_t) :: weights(8), part(8)
        type(error_t), allocatable :: err
        call csr_from_edges(8, a, b, xadj, adjncy)
        weights = 1
        call partition_graph(xadj, adjncy, weights, 2, part, err)
        CHECK_TRUE(.not. allocated(err), 'no error')
        CHECK_EQUAL(edge_cut(a, b, part), 1, 'only the bridge is cut')
        CHECK_TRUE(all(part(1:4) == part(1)), 'first clique in one part')
        CHECK_TRUE(all(part(5:8) == part(5)), 'second clique in one part')
        CHECK_TRUE(part(1) /= part(5), 'cliques in different parts')
    end subroutine test_two_cliques

    ! A path of 8 with weights 3, 3, 1, 1, 1, 1, 1, 1: the balanced split with one cut (6 + 6)
    ! is {1, 2} | {3 .. 8}, not the middle cut of unit weights, so the weights reach METIS.
    subroutine test_vertex_weights_balanced()
        integer, parameter :: a(7) = [1, 2, 3, 4, 5, 6, 7], b(7) = [2, 3, 4, 5, 6, 7, 8]
        integer(c_int32_t), allocatable :: xadj(:), adjncy(:)
        integer(c_int32_t) :: weights(8), part(8)
        type(error_t), allocatable :: err
        call csr_from_edges(8, a, b, xadj, adjncy)
        weights = [3, 3, 1, 1, 1, 1, 1, 1]
        call partition_graph(xadj, adjncy, weights, 2, part, err)
        CHECK_TRUE(.not. allocated(err), 'no error')
        CHECK_EQUAL(int(sum(weights, mask=part == part(1))), 6, 'weight of the first part')
        CHECK_EQUAL(int(sum(weights, mask=part /= part(1))), 6, 'weight of the second part')
        CHECK_EQUAL(edge_cut(a, b, part), 1, 'one cut edge')
        CHECK_TRUE(part(2) == part(1) .and. part(3) /= part(1), 'cut between vertices 2 and 3')
    end subroutine test_vertex_weights_balanced

    ! 4 x 4 grid graph in 4 parts: 4 vertices each; the quadrants cut 8 of the 24 edges (the
    ! optimum: a part of 4 grid vertices has at most 4 inner edges), four strips cut 12. The
    ! partition must be at least as good as the strips.
    subroutine test_grid_in_4_parts()
        integer :: a(24), b(24), i, j, k, p
        integer(c_int32_t), allocatable :: xadj(:), adjncy(:)
        integer(c_int32_t) :: weights(16), part(16)
        type(error_t), allocatable :: err
        k = 0
        do j = 0, 3
            do i = 0, 3
                if (i < 3) then
                    k = k + 1
                    a(k) = 4 * j + i + 1
                    b(k) = a(k) + 1
                end if
                if (j < 3) then
                    k = k + 1
                    a(k) = 4 * j + i + 1
                    b(k) = a(k) + 4
                end if
            end do
        end do
        CHECK_EQUAL(k, 24, 'edges of a 4 x 4 grid')
        call csr_from_edges(16, a, b, xadj, adjncy)
        weights = 1
        call partition_graph(xadj, adjncy, weights, 4, part, err)
        CHECK_TRUE(.not. allocated(err), 'no error')
        do p = 0, 3
            CHECK_EQUAL(count(part == p), 4, 'four vertices per part')
        end do
        CHECK_TRUE(edge_cut(a, b, part) <= 12, 'cut no worse than four strips')
    end subroutine test_grid_in_4_parts

    ! Debian's METIS 5.1 dies with SIGFPE for nparts = 1 (DESIGN.md 5), so this test also
    ! shows that METIS is not called.
    subroutine test_one_part_without_metis()
        integer, parameter :: a(3) = [1, 2, 3], b(3) = [2, 3, 4]
        integer(c_int32_t), allocatable :: xadj(:), adjncy(:)
        integer(c_int32_t) :: weights(4), part(4), one_part(1), xadj1(2), adjncy1(0)
        type(error_t), allocatable :: err
        call csr_from_edges(4, a, b, xadj, adjncy)
        weights = 1
        part = 7
        call partition_graph(xadj, adjncy, weights, 1, part, err)
        CHECK_TRUE(.not. allocated(err), 'no error')
        CHECK_TRUE(all(part == 0), 'all vertices in part 0')
        xadj1 = 0
        one_part = 7
        call partition_graph(xadj1, adjncy1, weights(1:1), 3, one_part, err)
        CHECK_TRUE(.not. allocated(err), 'single vertex: no error')
        CHECK_EQUAL(int(one_part(1)), 0, 'single vertex in part 0')
    end subroutine test_one_part_without_metis

    subroutine test_inconsistent_sizes()
        integer, parameter :: a(3) = [1, 2, 3], b(3) = [2, 3, 4]
        integer(c_int32_t), allocatable :: xadj(:), adjncy(:)
        integer(c_int32_t) :: weights(4), part(4), short_part(3)
        type(error_t), allocatable :: err
        call csr_from_edges(4, a, b, xadj, adjncy)
        weights = 1
        call partition_graph(xadj, adjncy, weights, 2, short_part, err)
        CHECK_TRUE(allocated(err), 'part of the wrong size')
        if (allocated(err)) then
            CHECK_CONTAINS(err%message, 'inconsistent sizes', 'message')
            CHECK_EQUAL(err%routine, 'partition_graph', 'routine')
        end if
        call partition_graph(xadj, adjncy, weights(1:3), 2, part, err)
        CHECK_TRUE(allocated(err), 'weights of the wrong size')
        call partition_graph(xadj, adjncy, weights, 0, part, err)
        CHECK_TRUE(allocated(err), 'nparts = 0')
    end subroutine test_inconsistent_sizes

    subroutine test_version()
        character(len=:), allocatable :: text
        integer :: first_dot, second_dot
        text = metis_version()
        CHECK_EQUAL(text(1:min(4, len(text))), '5.1.', 'METIS 5.1 (idx_t and real_t of 32 bits)')
        first_dot = index(text, '.')
        second_dot = index(text, '.', back=.true.)
        CHECK_TRUE(second_dot > first_dot + 1 .and. second_dot < len(text), 'major.minor.subminor')
        CHECK_EQUAL(verify(text, '0123456789.'), 0, 'digits and dots only')
    end subroutine test_version

end module rs_test_parallel_metis

!> Test program: runs the tests of rs_test_parallel_metis; exits non-zero if any failed.
program test_metis
    use rs_test_parallel_metis, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_metis
