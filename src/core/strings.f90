!> String helpers: case folding, number formatting and the edit distance behind "did you mean"
!> suggestions for misspelled input names (DESIGN.md §6).
module rs_core_strings
    use, intrinsic :: iso_fortran_env, only: int64
    use, intrinsic :: iso_c_binding, only: c_char, c_null_char
    use rs_core_kinds, only: rk
    implicit none
    private

    public :: str_significant, to_lower, str, edit_distance, closest_name, vector_text, did_you_mean
    public :: to_c_string, from_c_string, split_list, append_joined

    !> Text built by appending pieces, grown by doubling: appending n pieces costs time linear
    !> in the total length (appending to a deferred-length string copies all of it each time,
    !> quadratic in a big scene or plan; issue 21 item 17).
    type, public :: text_buffer_t
        character(len=:), allocatable, private :: buffer
        integer, private :: used = 0
    contains
        procedure :: append => text_buffer_append
        !> The text appended so far.
        procedure :: text => text_buffer_text
    end type text_buffer_t

    !> Shortest readable text of a number.
    interface str
        module procedure str_int, str_real
    end interface str

contains

    !> `value` with `digits` significant digits, for people (timings, progress): "1.23e-03".
    pure function str_significant(value, digits) result(text)
        real(rk), intent(in) :: value
        integer, intent(in) :: digits
        character(len=:), allocatable :: text
        character(len=40) :: buffer, form
        write(form, '(a,i0,a,i0,a)') '(es', digits + 8, '.', max(digits - 1, 0), ')'
        write(buffer, form) value
        text = trim(adjustl(buffer))
    end function str_significant

    !> `text` with ASCII upper-case letters folded to lower case.
    pure function to_lower(text) result(lower)
        character(len=*), intent(in) :: text
        character(len=len(text)) :: lower
        integer :: i, code
        lower = text
        do i = 1, len(text)
            code = iachar(text(i:i))
            if (code >= iachar('A') .and. code <= iachar('Z')) lower(i:i) = achar(code + 32)
        end do
    end function to_lower

    pure function str_int(value) result(text)
        integer, intent(in) :: value
        character(len=:), allocatable :: text
        character(len=24) :: buffer
        integer(int64) :: rest
        integer :: first
        ! Digit by digit rather than an internal write, which costs about a microsecond: the
        ! XDMF sidecar of a long run formats hundreds of thousands of integers.
        rest = abs(int(value, int64))
        first = len(buffer) + 1
        do
            first = first - 1
            buffer(first:first) = achar(iachar('0') + int(mod(rest, 10_int64)))
            rest = rest / 10_int64
            if (rest == 0_int64) exit
        end do
        if (value < 0) then
            first = first - 1
            buffer(first:first) = '-'
        end if
        text = buffer(first:)
    end function str_int

    !> Real as the shortest text that reads back to the same double: positional notation for
    !> magnitudes in [1e-3, 1e7), scientific otherwise (e.g. 0.01, 7800.0, 2.1e+11).
    pure function str_real(value) result(text)
        real(rk), intent(in) :: value
        character(len=:), allocatable :: text
        character(len=40) :: buffer
        real(rk) :: back
        integer :: digits, ios
        if (value /= 0.0_rk .and. abs(value) >= 1.0e-3_rk .and. abs(value) < 1.0e7_rk) then
            do digits = 1, 20
                write(buffer, '(f40.' // str_int(digits) // ')') value
                read(buffer, *, iostat=ios) back
                if (ios == 0 .and. back == value) exit
            end do
            text = trim(adjustl(buffer))
            if (text(1:1) == '.') text = '0' // text
            if (text(1:2) == '-.') text = '-0' // text(2:)
            if (text(len(text):len(text)) == '.') text = text // '0'
            return
        end if
        ! A short trial of a value near huge() rounds past it and would overflow when read back
        ! (a trapped FPE in checked builds): such values take all 17 digits at once.
        do digits = merge(17, 1, abs(value) > 1.0e308_rk), 17
            ! The explicit exponent width keeps the letter E for three-digit exponents.
            write(buffer, '(es26.' // str_int(digits - 1) // 'e3)') value
            read(buffer, *, iostat=ios) back
            if (ios == 0 .and. back == value) exit
        end do
        text = trim(adjustl(buffer))
        call trim_mantissa(text)
    end function str_real

    !> 1.50000E+000 -> 1.5, 2.0000E-003 -> 2.0e-03, 1.5E-100 -> 1.5e-100: one digit after the
    !> point at least, exponents with at least two digits.
    pure subroutine trim_mantissa(text)
        character(len=:), allocatable, intent(inout) :: text
        integer :: e, last
        character(len=:), allocatable :: mantissa, exponent
        e = scan(text, 'Ee')
        if (e == 0) return
        mantissa = text(1:e - 1)
        exponent = text(e + 1:)
        last = len(mantissa)
        do while (last > 1)
            if (mantissa(last:last) /= '0' .or. mantissa(last - 1:last - 1) == '.') exit
            last = last - 1
        end do
        mantissa = mantissa(1:last)
        if (mantissa(len(mantissa):len(mantissa)) == '.') mantissa = mantissa // '0'
        do while (len(exponent) > 3)
            if (exponent(2:2) /= '0') exit
            exponent = exponent(1:1) // exponent(3:)
        end do
        if (verify(exponent(2:), '0') == 0) then
            text = mantissa
        else
            text = mantissa // 'e' // exponent
        end if
    end subroutine trim_mantissa

    !> Levenshtein distance between two strings (case-sensitive; fold first if needed).
    pure integer function edit_distance(a, b) result(distance)
        character(len=*), intent(in) :: a, b
        integer :: previous(0:len(b)), current(0:len(b))
        integer :: i, j, cost
        previous = [(j, j = 0, len(b))]
        do i = 1, len(a)
            current(0) = i
            do j = 1, len(b)
                cost = merge(0, 1, a(i:i) == b(j:j))
                current(j) = min(previous(j) + 1, current(j - 1) + 1, previous(j - 1) + cost)
            end do
            previous = current
        end do
        distance = previous(len(b))
    end function edit_distance

    !> The entry of `names` closest to `name`, or '' if none is close enough to be a likely
    !> misspelling (distance at most 2, or at most a third of the name's length).
    pure function closest_name(name, names) result(best)
        character(len=*), intent(in) :: name
        character(len=*), intent(in) :: names(:)
        character(len=:), allocatable :: best
        integer :: i, d, best_distance, limit
        best = ''
        best_distance = huge(1)
        limit = max(2, len_trim(name) / 3)
        do i = 1, size(names)
            d = edit_distance(to_lower(trim(name)), to_lower(trim(names(i))))
            if (d < best_distance) then
                best_distance = d
                best = trim(names(i))
            end if
        end do
        if (best_distance > limit) best = ''
    end function closest_name

    !> '; did you mean "x"?' when `name` is close to one of `names` (closest_name), else ''.
    pure function did_you_mean(name, names) result(text)
        character(len=*), intent(in) :: name
        character(len=*), intent(in) :: names(:)
        character(len=:), allocatable :: text, best
        best = closest_name(name, names)
        text = ''
        if (len(best) > 0) text = '; did you mean "' // best // '"?'
    end function did_you_mean

    !> "x, y, z": the entries of `v` in shortest exact form (`str`), comma-separated.
    pure function vector_text(v) result(text)
        real(rk), intent(in) :: v(:)
        character(len=:), allocatable :: text
        integer :: i
        text = ''
        do i = 1, size(v)
            if (i > 1) text = text // ', '
            text = text // str(v(i))
        end do
    end function vector_text

    !> `text` as a NUL-terminated C string.
    pure function to_c_string(text) result(chars)
        character(len=*), intent(in) :: text
        character(kind=c_char) :: chars(len(text) + 1)
        integer :: i
        do i = 1, len(text)
            chars(i) = text(i:i)
        end do
        chars(len(text) + 1) = c_null_char
    end function to_c_string

    !> The characters of a C string up to its NUL (or the whole buffer).
    pure function from_c_string(chars) result(text)
        character(kind=c_char), intent(in) :: chars(:)
        character(len=:), allocatable :: text
        integer :: i, n
        n = size(chars)
        do i = 1, size(chars)
            if (chars(i) == c_null_char) then
                n = i - 1
                exit
            end if
        end do
        allocate(character(len=n) :: text)
        do i = 1, n
            text(i:i) = chars(i)
        end do
    end function from_c_string

    !> Append `part` to `text`, after `separator` unless `text` is empty (a list in words).
    pure subroutine append_joined(text, separator, part)
        character(len=:), allocatable, intent(inout) :: text
        character(len=*), intent(in) :: separator, part
        if (len(text) > 0) text = text // separator
        text = text // part
    end subroutine append_joined

    !> The names of a '|'-separated list ('a|b|c'; an empty list gives one blank name).
    pure function split_list(list) result(names)
        character(len=*), intent(in) :: list
        character(len=32), allocatable :: names(:)
        integer :: start, bar, k
        ! Counted first and filled in place: growing a character array by
        ! constructor trips gfortran's length check (-fcheck=all).
        allocate(names(count([(list(k:k) == '|', k = 1, len_trim(list))]) + 1))
        start = 1
        do k = 1, size(names)
            bar = index(list(start:), '|')
            if (bar == 0) then
                names(k) = list(start:len_trim(list))
            else
                names(k) = list(start:start + bar - 2)
                start = start + bar
            end if
        end do
    end function split_list

    subroutine text_buffer_append(this, piece)
        class(text_buffer_t), intent(inout) :: this
        character(len=*), intent(in) :: piece
        character(len=:), allocatable :: grown
        if (.not. allocated(this%buffer)) allocate(character(len=max(4096, 2 * len(piece))) :: &
            this%buffer)
        if (this%used + len(piece) > len(this%buffer)) then
            allocate(character(len=2 * (this%used + len(piece))) :: grown)
            grown(1:this%used) = this%buffer(1:this%used)
            call move_alloc(grown, this%buffer)
        end if
        this%buffer(this%used + 1:this%used + len(piece)) = piece
        this%used = this%used + len(piece)
    end subroutine text_buffer_append

    function text_buffer_text(this) result(text)
        class(text_buffer_t), intent(in) :: this
        character(len=:), allocatable :: text
        if (allocated(this%buffer)) then
            text = this%buffer(1:this%used)
        else
            text = ''
        end if
    end function text_buffer_text

end module rs_core_strings
