!> A checksum of the checkpoint that a restart verifies (issue 21 item 21; docs/user/output.md
!> "Checksums"): HDF5's own Fletcher-32 filter needs chunked datasets and parallel HDF5 1.10
!> cannot write filtered datasets collectively, so rodsolve computes the same kind of sum itself.
!> It is Fletcher's checksum (J. G. Fletcher, IEEE Trans. Commun. 30 (1982) 247; the algorithm
!> of HDF5's H5checksum.c) on 32-bit words with sums modulo 2^32 - 1: a changed word, a swap of
!> two words, and any burst of up to 32 bits change it.
module rs_io_checksum
    use, intrinsic :: iso_fortran_env, only: int32, int64
    use rs_core_kinds, only: rk
    implicit none
    private

    public :: checkpoint_checksum

    integer(int64), parameter :: modulus = 4294967295_int64

contains

    !> The two Fletcher sums (each below 2^32 - 1, stored as the signed 32-bit integers of the
    !> same bits) of the checkpoint's state, internal values, step, records and time, in that
    !> order, reals as their IEEE bytes.
    pure function checkpoint_checksum(state, internal, step, records, time) result(sums)
        real(rk), intent(in) :: state(:), internal(:), time
        integer, intent(in) :: step, records
        integer :: sums(2)
        integer(int64) :: a, b
        a = 0
        b = 0
        call add_words(transfer(state, [0_int32]), a, b)
        call add_words(transfer(internal, [0_int32]), a, b)
        call add_words(int([step, records], int32), a, b)
        call add_words(transfer(time, [0_int32]), a, b)
        sums = [signed_32(a), signed_32(b)]
    end function checkpoint_checksum

    !> Fletcher's two running sums over `words`, each word's bits as an unsigned value.
    pure subroutine add_words(words, a, b)
        integer(int32), intent(in) :: words(:)
        integer(int64), intent(inout) :: a, b
        integer :: k
        do k = 1, size(words)
            ! Below 2^32 each, so the sums stay below 2^34 before the modulo.
            a = mod(a + iand(int(words(k), int64), modulus), modulus)
            b = mod(b + a, modulus)
        end do
    end subroutine add_words

    !> The signed 32-bit integer with the bits of `value` (0 <= value < 2^32).
    pure integer function signed_32(value)
        integer(int64), intent(in) :: value
        if (value >= 2147483648_int64) then
            signed_32 = int(value - 4294967296_int64)
        else
            signed_32 = int(value)
        end if
    end function signed_32

end module rs_io_checksum
