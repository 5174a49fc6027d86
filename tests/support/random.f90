!> Reproducible random samples for tests: a fixed seed per test program, uniform numbers and
!> vectors, and uniformly distributed unit vectors (rotation axes).
module rs_test_random
    use rs_core_kinds, only: rk
    implicit none
    private

    public :: set_random_seed, random_unit_vector, uniform, random_vector

contains

    !> Seed the intrinsic generator with base + stride * i, i = 1 .. the seed size.
    subroutine set_random_seed(base, stride)
        integer, intent(in) :: base, stride
        integer :: n, i
        integer, allocatable :: seed(:)
        call random_seed(size=n)
        allocate(seed(n))
        seed = [(base + stride * i, i = 1, n)]
        call random_seed(put=seed)
    end subroutine set_random_seed

    !> A unit vector uniformly distributed on the sphere (rejection from the unit ball, with
    !> vectors too short to normalize accurately rejected too).
    function random_unit_vector() result(axis)
        real(rk) :: axis(3)
        do
            call random_number(axis)
            axis = 2.0_rk * axis - 1.0_rk
            if (norm2(axis) > 0.1_rk .and. norm2(axis) <= 1.0_rk) exit
        end do
        axis = axis / norm2(axis)
    end function random_unit_vector

    !> A number uniform in [lo, hi].
    function uniform(lo, hi) result(x)
        real(rk), intent(in) :: lo, hi
        real(rk) :: x
        call random_number(x)
        x = lo + (hi - lo) * x
    end function uniform

    !> n entries uniform in [-scale, scale].
    function random_vector(n, scale) result(x)
        integer, intent(in) :: n
        real(rk), intent(in) :: scale
        real(rk) :: x(n)
        call random_number(x)
        x = scale * (2.0_rk * x - 1.0_rk)
    end function random_vector

end module rs_test_random
