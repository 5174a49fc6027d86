#include "rs_assert.h"
!> Unit tests of rs_core_strings: case folding, integer text, the shortest exact text of a real
!> (read back bitwise over magnitudes 1e-300 .. 1e300, documented forms), the Levenshtein
!> distance on textbook pairs and the threshold of closest_name.
module rs_test_core_strings
    use rs_core_kinds, only: rk
    use rs_test_assert, only: run_test, assert_true, assert_equal
    use rs_core_strings, only: to_lower, str, edit_distance, closest_name, split_list, text_buffer_t
    implicit none
    private

    public :: run_all_tests

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('to_lower_ascii_only', test_to_lower_ascii_only)
        call run_test('str_int', test_str_int)
        call run_test('str_real_documented_forms', test_str_real_documented_forms)
        call run_test('str_real_reads_back_random', test_str_real_reads_back_random)
        call run_test('str_real_is_shortest', test_str_real_is_shortest)
        call run_test('str_real_three_digit_exponent', test_str_real_three_digit_exponent)
        call run_test('edit_distance_known_values', test_edit_distance_known_values)
        call run_test('edit_distance_metric_properties', test_edit_distance_metric_properties)
        call run_test('closest_name_threshold', test_closest_name_threshold)
        call run_test('str_real_near_huge', test_str_real_near_huge)
        call run_test('split_list', test_split_list)
        call run_test('text_buffer_grows', test_text_buffer_grows)
    end subroutine run_all_tests

    subroutine test_to_lower_ascii_only()
        CHECK_EQUAL(to_lower('Hello World_42 %EI1'), 'hello world_42 %ei1', 'mixed text')
        CHECK_EQUAL(to_lower('AZaz@[`{'), 'azaz@[`{', 'letters only; neighbours of A-Z kept')
        CHECK_EQUAL(to_lower(''), '', 'empty text')
        CHECK_EQUAL(len(to_lower('AB  ')), 4, 'length (trailing blanks) kept')
    end subroutine test_to_lower_ascii_only

    subroutine test_str_int()
        character(len=24) :: expected
        integer :: k, value
        CHECK_EQUAL(str(0), '0', 'zero')
        CHECK_EQUAL(str(42), '42', 'positive')
        CHECK_EQUAL(str(-7), '-7', 'negative')
        CHECK_EQUAL(str(huge(1)), '2147483647', 'largest 32-bit integer')
        CHECK_EQUAL(str(-huge(1) - 1), '-2147483648', 'smallest 32-bit integer')
        ! Digit by digit, it must agree with the I0 edit descriptor at every number of digits.
        do k = 0, 9
            value = 10**k - 1
            write(expected, '(i0)') value
            CHECK_EQUAL(str(value), trim(expected), 'a run of nines')
            write(expected, '(i0)') -(value + 1)
            CHECK_EQUAL(str(-(value + 1)), trim(expected), 'a negative power of ten')
        end do
    end subroutine test_str_int

    ! The forms named in the documentation of str_real: positional in [1e-3, 1e7), scientific
    ! with "e" and a signed two-digit exponent otherwise; the shortest decimal of 0.1 is "0.1".
    subroutine test_str_real_documented_forms()
        CHECK_EQUAL(str(0.01_rk), '0.01', 'doc example 0.01')
        CHECK_EQUAL(str(7800.0_rk), '7800.0', 'doc example 7800.0')
        CHECK_EQUAL(str(2.1e11_rk), '2.1e+11', 'doc example 2.1e+11')
        CHECK_EQUAL(str(0.1_rk), '0.1', '0.1')
        CHECK_EQUAL(str(-0.5_rk), '-0.5', 'negative below 1')
        CHECK_EQUAL(str(1.0_rk), '1.0', 'one')
        CHECK_EQUAL(str(0.0_rk), '0.0', 'zero')
        CHECK_EQUAL(str(1.0e-3_rk), '0.001', 'lower end of the positional range')
        CHECK_EQUAL(str(9999999.5_rk), '9999999.5', 'upper end of the positional range')
        CHECK_EQUAL(str(1.0e7_rk), '1.0e+07', 'first scientific value above')
        CHECK_EQUAL(str(2.5e-4_rk), '2.5e-04', 'scientific below 1e-3')
        CHECK_EQUAL(str(-6.02e23_rk), '-6.02e+23', 'negative scientific')
        CHECK_EQUAL(str(1.0_rk / 3.0_rk), '0.3333333333333333', '1/3 needs 16 digits')
    end subroutine test_str_real_documented_forms

    ! Random doubles with decimal exponents uniform in [-300, 300], both signs: the text reads
    ! back (list-directed, as the namelist reader does) to the identical double.
    subroutine test_str_real_reads_back_random()
        integer, parameter :: n = 20000
        real(rk) :: u(3), value, back
        character(len=:), allocatable :: text
        integer :: i, ios, n_bad, seed_size
        integer, allocatable :: seed(:)
        call random_seed(size=seed_size)
        allocate(seed(seed_size))
        seed = [(1234567 + 7919 * i, i = 1, seed_size)]
        call random_seed(put=seed)
        n_bad = 0
        do i = 1, n
            call random_number(u)
            value = (1.0_rk + 9.0_rk * u(1)) * 10.0_rk**(nint(600.0_rk * u(2)) - 300)
            if (u(3) < 0.5_rk) value = -value
            text = str(value)
            read(text, *, iostat=ios) back
            if (ios /= 0 .or. back /= value) then
                n_bad = n_bad + 1
                if (n_bad <= 5) then
                    CHECK_TRUE(.false., 'reads back: "' // text // '"')
                end if
            end if
        end do
        CHECK_EQUAL(n_bad, 0, 'values whose text does not read back')
        ! Neighbours of the ends of the positional range, and the smallest normal double.
        call check_reads_back(nearest(1.0_rk, 1.0_rk))
        call check_reads_back(nearest(1.0e-3_rk, -1.0_rk))
        call check_reads_back(nearest(1.0e7_rk, -1.0_rk))
        call check_reads_back(-tiny(1.0_rk))
    end subroutine test_str_real_reads_back_random

    ! The largest doubles: str must not read back a shorter text that overflows (which stops a
    ! program built with -ffpe-trap=overflow, the Debug configuration). Run last, as such a
    ! failure ends the program.
    subroutine test_str_real_near_huge()
        call check_reads_back(huge(1.0_rk))
        call check_reads_back(-1.6e308_rk)
    end subroutine test_str_real_near_huge

    subroutine check_reads_back(value)
        real(rk), intent(in) :: value
        real(rk) :: back
        character(len=:), allocatable :: text
        integer :: ios
        text = str(value)
        read(text, *, iostat=ios) back
        CHECK_EQUAL(ios, 0, 'readable: "' // text // '"')
        CHECK_TRUE(back == value, 'reads back bitwise: "' // text // '"')
    end subroutine check_reads_back

    ! Shortest: a value that is exactly a short decimal (k significant digits, the nearest
    ! double to it) comes out with k significant digits.
    subroutine test_str_real_is_shortest()
        CHECK_EQUAL(significant_digits(str(1.25_rk)), 3, '1.25')
        CHECK_EQUAL(significant_digits(str(123456.7_rk)), 7, '123456.7')
        CHECK_EQUAL(significant_digits(str(3.0e-20_rk)), 1, '3e-20')
        CHECK_EQUAL(significant_digits(str(-4.56789e15_rk)), 6, '-4.56789e15')
        CHECK_EQUAL(significant_digits(str(0.1_rk + 0.2_rk)), 17, '0.1 + 0.2 needs 17 digits')
    end subroutine test_str_real_is_shortest

    ! Exponents of three digits are written like the others ("e" and one digit after the
    ! point), so that the resolved scene is readable by other tools (Python's float()).
    subroutine test_str_real_three_digit_exponent()
        CHECK_EQUAL(str(1.0e-300_rk), '1.0e-300', '1e-300')
        CHECK_EQUAL(str(-3.0e300_rk), '-3.0e+300', '-3e300')
        CHECK_EQUAL(str(1.5e-100_rk), '1.5e-100', '1.5e-100')
    end subroutine test_str_real_three_digit_exponent

    ! Significant digits of the mantissa of a number's text (leading zeros and a trailing
    ! ".0" not counted).
    pure integer function significant_digits(text) result(n)
        character(len=*), intent(in) :: text
        character(len=:), allocatable :: mantissa, digits
        integer :: e, i
        e = scan(text, 'eE')
        mantissa = text
        if (e > 0) mantissa = text(1:e - 1)
        digits = ''
        do i = 1, len(mantissa)
            if (verify(mantissa(i:i), '0123456789') == 0) digits = digits // mantissa(i:i)
        end do
        i = verify(digits, '0')
        if (i == 0) then
            n = 0
            return
        end if
        digits = digits(i:)
        n = len(digits)
        do while (n > 1)
            if (digits(n:n) /= '0') exit
            n = n - 1
        end do
    end function significant_digits

    ! Textbook pairs (Levenshtein; Wagner & Fischer).
    subroutine test_edit_distance_known_values()
        CHECK_EQUAL(edit_distance('kitten', 'sitting'), 3, 'kitten / sitting')
        CHECK_EQUAL(edit_distance('saturday', 'sunday'), 3, 'saturday / sunday')
        CHECK_EQUAL(edit_distance('flaw', 'lawn'), 2, 'flaw / lawn')
        CHECK_EQUAL(edit_distance('lenght', 'length'), 2, 'transposition costs 2')
        CHECK_EQUAL(edit_distance('', 'abc'), 3, 'empty / abc')
        CHECK_EQUAL(edit_distance('abcd', ''), 4, 'abcd / empty')
        CHECK_EQUAL(edit_distance('', ''), 0, 'both empty')
        CHECK_EQUAL(edit_distance('rod', 'rod'), 0, 'identical')
        CHECK_EQUAL(edit_distance('EI1', 'ei1'), 2, 'case-sensitive')
        CHECK_EQUAL(edit_distance('abc', 'xyz'), 3, 'all substituted')
    end subroutine test_edit_distance_known_values

    ! Symmetry, triangle inequality and the length bounds on a few words.
    subroutine test_edit_distance_metric_properties()
        character(len=12), parameter :: words(6) = [character(len=12) :: 'n_elements', &
            'n_elemnts', 'elements', 'degree', 'n_gauss', 'direction']
        integer :: i, j, k, dij, dik, dkj
        do i = 1, size(words)
            do j = 1, size(words)
                dij = edit_distance(trim(words(i)), trim(words(j)))
                CHECK_EQUAL(dij, edit_distance(trim(words(j)), trim(words(i))), 'symmetric')
                CHECK_TRUE(dij >= abs(len_trim(words(i)) - len_trim(words(j))), 'lower bound')
                CHECK_TRUE(dij <= max(len_trim(words(i)), len_trim(words(j))), 'upper bound')
                CHECK_EQUAL(dij == 0, i == j, 'zero only for equal words')
                do k = 1, size(words)
                    dik = edit_distance(trim(words(i)), trim(words(k)))
                    dkj = edit_distance(trim(words(k)), trim(words(j)))
                    CHECK_TRUE(dij <= dik + dkj, 'triangle inequality')
                end do
            end do
        end do
    end subroutine test_edit_distance_metric_properties

    ! Limit: max(2, len_trim(name) / 3); names compared without case; ties go to the first.
    subroutine test_closest_name_threshold()
        character(len=16), parameter :: names(4) = [character(len=16) :: 'length', 'n_elements', &
            'radius', 'EI1']
        character(len=9) :: one(1)
        character(len=3) :: two(2), none(0)
        CHECK_EQUAL(closest_name('lenght', names), 'length', 'distance 2 accepted')
        CHECK_EQUAL(closest_name('n_elemnts', names), 'n_elements', 'distance 1')
        CHECK_EQUAL(closest_name('LENGTH', names), 'length', 'case folded')
        CHECK_EQUAL(closest_name('ei1', names), 'EI1', 'spelling of the list returned')
        CHECK_EQUAL(closest_name('xyzzy', names), '', 'nothing close')
        ! 4 characters: limit 2.
        one(1) = 'abcd'
        CHECK_EQUAL(closest_name('abxy', one), 'abcd', 'length 4 at distance 2')
        CHECK_EQUAL(closest_name('axyz', one), '', 'length 4 at distance 3')
        ! 9 characters: limit 3.
        one(1) = 'abcdefghi'
        CHECK_EQUAL(closest_name('abcdefxyz', one), 'abcdefghi', 'length 9 at distance 3')
        CHECK_EQUAL(closest_name('abcdewxyz', one), '', 'length 9 at distance 4')
        two = [character(len=3) :: 'bat', 'cab']
        CHECK_EQUAL(closest_name('cat', two), 'bat', 'tie goes to the first')
        two = [character(len=3) :: 'bc', 'rod']
        CHECK_EQUAL(closest_name('rod', two), 'rod', 'exact match')
        CHECK_EQUAL(closest_name('rod', none), '', 'empty list')
    end subroutine test_closest_name_threshold

    !> '|'-separated lists as the capability rows and allowed values write them.
    subroutine test_split_list()
        character(len=32), allocatable :: names(:)
        character(len=:), allocatable :: joined
        names = split_list('clamped|pinned|free')
        CHECK_EQUAL(size(names), 3, 'three names')
        joined = trim(names(1)) // ',' // trim(names(2)) // ',' // trim(names(3))
        CHECK_EQUAL(joined, 'clamped,pinned,free', 'in order')
        names = split_list('one')
        CHECK_EQUAL(size(names), 1, 'a single name')
        CHECK_EQUAL(trim(names(1)), 'one', 'the name itself')
    end subroutine test_split_list

    !> Appending 10000 pieces past the initial size keeps every byte in order.
    subroutine test_text_buffer_grows()
        type(text_buffer_t) :: buffer
        character(len=:), allocatable :: text
        integer :: i
        CHECK_EQUAL(len(buffer%text()), 0, 'empty before any append')
        do i = 1, 10000
            call buffer%append(achar(iachar('a') + mod(i, 26)))
        end do
        text = buffer%text()
        CHECK_EQUAL(len(text), 10000, 'every piece kept')
        text = text(1:3) // text(9998:10000)
        ! Piece i is letter mod(i, 26): 1, 2, 3 -> b, c, d; 9998, 9999, 10000 -> 14, 15, 16 -> o, p, q.
        CHECK_EQUAL(text, 'bcdopq', 'first and last pieces in order')
    end subroutine test_text_buffer_grows

end module rs_test_core_strings

!> Test program: runs the tests of rs_test_core_strings; exits non-zero if any failed.
program test_strings
    use rs_test_core_strings, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_strings
