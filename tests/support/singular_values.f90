!> Singular values of a dense matrix for tests (LAPACK's dgesvd), with the floating-point traps
!> of the Debug build held off during the call: its internal scaling may underflow harmlessly.
module rs_test_singular_values
    use, intrinsic :: ieee_exceptions, only: ieee_usual, ieee_get_halting_mode, &
        ieee_set_halting_mode, ieee_set_flag
    use rs_core_kinds, only: rk
    implicit none
    private

    public :: singular_values

    interface
        subroutine dgesvd(jobu, jobvt, m, n, a, lda, s, u, ldu, vt, ldvt, work, lwork, info)
            import :: rk
            character(len=1), intent(in) :: jobu, jobvt
            integer, intent(in) :: m, n, lda, ldu, ldvt, lwork
            real(rk), intent(inout) :: a(lda, *)
            real(rk), intent(out) :: s(*), u(ldu, *), vt(ldvt, *), work(*)
            integer, intent(out) :: info
        end subroutine dgesvd
    end interface

contains

    !> The singular values of a, largest first; info is dgesvd's (0: success).
    function singular_values(a, info) result(s)
        real(rk), intent(in) :: a(:, :)
        integer, intent(out) :: info
        real(rk) :: s(min(size(a, 1), size(a, 2)))
        real(rk) :: work_a(size(a, 1), size(a, 2)), u(1, 1), vt(1, 1)
        real(rk), allocatable :: work(:)
        logical :: halting(size(ieee_usual))
        work_a = a
        allocate(work(10 * max(size(a, 1), size(a, 2)) + 1000))
        call ieee_get_halting_mode(ieee_usual, halting)
        call ieee_set_halting_mode(ieee_usual, .false.)
        call dgesvd('N', 'N', size(a, 1), size(a, 2), work_a, size(a, 1), s, u, 1, vt, 1, work, &
            size(work), info)
        call ieee_set_flag(ieee_usual, .false.)
        call ieee_set_halting_mode(ieee_usual, halting)
    end function singular_values

end module rs_test_singular_values
