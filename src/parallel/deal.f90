!> Dealing independent pieces of work to ranks (DESIGN.md §5): sweep members, uncoupled systems
!> of rods. Pure: the same answer on every rank without communication.
module rs_parallel_deal
    use rs_core_kinds, only: rk
    implicit none
    private

    public :: deal_by_cost

contains

    !> Rank (0 .. n_ranks - 1) of each piece of work: longest processing time first, i.e. the
    !> pieces by decreasing estimated cost (ties: lower index first), each to the rank with the
    !> least cost so far (ties: lower rank). Greedy LPT is within 4/3 of the best makespan.
    pure function deal_by_cost(costs, n_ranks) result(owner)
        real(rk), intent(in) :: costs(:)
        integer, intent(in) :: n_ranks
        integer :: owner(size(costs))
        real(rk) :: load(0:max(n_ranks, 1) - 1)
        integer :: order(size(costs)), i, j, k, r
        order = [(i, i = 1, size(costs))]
        ! Insertion sort by decreasing cost, stable (counts are modest: thousands).
        do i = 2, size(order)
            k = order(i)
            j = i - 1
            do while (j >= 1)
                if (costs(order(j)) >= costs(k)) exit
                order(j + 1) = order(j)
                j = j - 1
            end do
            order(j + 1) = k
        end do
        load = 0.0_rk
        do i = 1, size(order)
            r = minloc(load, dim=1) - 1
            owner(order(i)) = r
            load(r) = load(r) + costs(order(i))
        end do
    end function deal_by_cost

end module rs_parallel_deal
