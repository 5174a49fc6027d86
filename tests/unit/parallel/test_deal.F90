#include "rs_assert.h"
!> Unit tests of rs_parallel_deal (deal_by_cost): equal costs go round robin; the largest
!> piece first to the least loaded rank (LPT) balances a known case exactly; one rank takes
!> everything; no pieces work; a sweep-like set of costs is balanced within 1 %.
module rs_test_parallel_deal
    use rs_core_kinds, only: rk
    use rs_test_assert, only: run_test, assert_true, assert_equal
    use rs_parallel_deal, only: deal_by_cost
    implicit none
    private

    public :: run_all_tests

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('equal_costs_round_robin', test_equal_costs_round_robin)
        call run_test('largest_first', test_largest_first)
        call run_test('one_rank', test_one_rank)
        call run_test('no_pieces', test_no_pieces)
        call run_test('balance_of_a_sweep', test_balance_of_a_sweep)
    end subroutine run_all_tests

    !> Equal costs: piece i on rank mod(i - 1, n), as a round robin.
    subroutine test_equal_costs_round_robin()
        integer :: owner(7), i
        owner = deal_by_cost([(1.0_rk, i = 1, 7)], 3)
        CHECK_TRUE(all(owner == [(mod(i - 1, 3), i = 1, 7)]), 'round robin for equal costs')
    end subroutine test_equal_costs_round_robin

    !> Costs 3, 5, 1, 4, 2, 3 on 2 ranks: LPT gives {5, 3, 1} and {4, 3, 2} (9 each).
    subroutine test_largest_first()
        integer :: owner(6)
        real(rk) :: costs(6)
        costs = [3.0_rk, 5.0_rk, 1.0_rk, 4.0_rk, 2.0_rk, 3.0_rk]
        owner = deal_by_cost(costs, 2)
        CHECK_EQUAL(owner(2), 0, 'the largest piece on rank 0')
        CHECK_EQUAL(owner(4), 1, 'the second on rank 1')
        CHECK_TRUE(sum(costs, mask=owner == 0) == 9.0_rk .and. sum(costs, mask=owner == 1) == 9.0_rk, 'both ranks carry 9')
    end subroutine test_largest_first

    subroutine test_one_rank()
        integer :: owner(4)
        owner = deal_by_cost([4.0_rk, 1.0_rk, 3.0_rk, 2.0_rk], 1)
        CHECK_TRUE(all(owner == 0), 'one rank takes everything')
    end subroutine test_one_rank

    subroutine test_no_pieces()
        integer, allocatable :: owner(:)
        real(rk), allocatable :: costs(:)
        allocate(costs(0))
        owner = deal_by_cost(costs, 4)
        CHECK_EQUAL(size(owner), 0, 'no pieces, no owners')
    end subroutine test_no_pieces

    !> 64 members whose cost grows like a sweep of the number of elements: on 2 ranks the
    !> slowest rank carries at most 1 % above the mean.
    subroutine test_balance_of_a_sweep()
        integer :: owner(64), i
        real(rk) :: costs(64), load(0:1)
        costs = [(real(4 + i, rk), i = 1, 64)]
        owner = deal_by_cost(costs, 2)
        load = [sum(costs, mask=owner == 0), sum(costs, mask=owner == 1)]
        CHECK_TRUE(maxval(load) / (sum(load) / 2.0_rk) <= 1.01_rk, 'balanced within 1 %')
    end subroutine test_balance_of_a_sweep

end module rs_test_parallel_deal

!> Test program: runs the tests of rs_test_parallel_deal; exits non-zero if any failed.
program test_deal
    use rs_test_parallel_deal, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_deal
