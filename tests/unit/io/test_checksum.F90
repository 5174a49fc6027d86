#include "rs_assert.h"
!> Unit tests of rs_io_checksum: Fletcher's two sums of the checkpoint's 32-bit words against
!> their closed form a = sum w_k, b = sum (n - k + 1) w_k (mod 2^32 - 1) for small words, a
!> word's top bit read unsigned, and the changes it must see: one flipped bit of a real, two
!> words swapped, a changed step.
module rs_test_io_checksum
    use, intrinsic :: iso_fortran_env, only: int64
    use rs_core_kinds, only: rk
    use rs_test_assert, only: run_test, assert_true, assert_equal
    use rs_io_checksum, only: checkpoint_checksum
    implicit none
    private

    public :: run_all_tests

contains

    subroutine run_all_tests()
        call run_test('closed_form', test_closed_form)
        call run_test('top_bit_unsigned', test_top_bit_unsigned)
        call run_test('sees_changes', test_sees_changes)
    end subroutine run_all_tests

    ! No state, no internal values, step 1, records 2, time 0: the words 1, 2, 0, 0, so
    ! a = 3 and b = 4*1 + 3*2 = 10.
    subroutine test_closed_form()
        real(rk) :: none(0)
        integer :: sums(2)
        sums = checkpoint_checksum(none, none, 1, 2, 0.0_rk)
        CHECK_EQUAL(sums(1), 3, 'a = 1 + 2')
        CHECK_EQUAL(sums(2), 10, 'b = 4*1 + 3*2')
    end subroutine test_closed_form

    ! The step -1 is the word 2^32 - 1 (read unsigned), which is 0 modulo 2^32 - 1; the records
    ! 7 follow: a = 7, b = 3*7 = 21. Read as a signed -1, a would be 6.
    subroutine test_top_bit_unsigned()
        real(rk) :: none(0)
        integer :: sums(2)
        sums = checkpoint_checksum(none, none, -1, 7, 0.0_rk)
        CHECK_EQUAL(sums(1), 7, 'a: -1 is 2^32 - 1, zero modulo 2^32 - 1')
        CHECK_EQUAL(sums(2), 21, 'b = 3*7')
    end subroutine test_top_bit_unsigned

    subroutine test_sees_changes()
        real(rk) :: state(40), changed(40), internal(3)
        integer :: sums(2), other(2), k
        integer(int64) :: bits
        state = [(sin(real(k, rk)), k = 1, 40)]
        internal = [0.5_rk, -2.0_rk, 1.0e-300_rk]
        sums = checkpoint_checksum(state, internal, 12, 13, 1.25_rk)
        do k = 1, 40
            changed = state
            bits = transfer(changed(k), bits)
            changed(k) = transfer(ieor(bits, shiftl(1_int64, mod(7 * k, 64))), changed(k))
            other = checkpoint_checksum(changed, internal, 12, 13, 1.25_rk)
            CHECK_TRUE(any(other /= sums), 'one flipped bit of the state')
        end do
        changed = state
        changed([3, 4]) = state([4, 3])
        other = checkpoint_checksum(changed, internal, 12, 13, 1.25_rk)
        CHECK_TRUE(any(other /= sums), 'two values swapped')
        other = checkpoint_checksum(state, internal, 11, 13, 1.25_rk)
        CHECK_TRUE(any(other /= sums), 'another step')
        other = checkpoint_checksum(state, internal, 12, 13, 1.25_rk)
        CHECK_TRUE(all(other == sums), 'the same values, the same sums')
    end subroutine test_sees_changes

end module rs_test_io_checksum

!> Test program: runs the tests of rs_test_io_checksum; exits non-zero if any failed.
program test_checksum
    use rs_test_io_checksum, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_checksum
