!> Splits namelist text into groups and assignments, with line numbers, before any value is
!> read (DESIGN.md §6): gfortran's namelist reader alone skips unknown groups silently, stops at
!> the first error and names no line. Each assignment is later read on its own, so every
!> problem can be reported with its file, line, group and variable.
!>
!> Syntax accepted: `&group name = value, name(2) = v, ... /` over any number of lines, `!`
!> comments outside quoted strings, strings in '...' or "..." (doubled quotes inside),
!> repeat counts `3*0.0`. Text outside groups is an error.
module rs_io_namelist_lexer
    use rs_core_error, only: error_list_t
    use rs_core_strings, only: to_lower, str
    implicit none
    private

    public :: assignment_t, group_chunk_t, split_namelist, remove_blanks

    !> One `target = value` of a group.
    type :: assignment_t
        !> The target as written, blanks removed (e.g. "start(2)").
        character(len=:), allocatable :: target
        !> Lower-case base name (e.g. "start").
        character(len=:), allocatable :: name
        logical :: subscripted = .false.
        !> Value text, one line, comments removed.
        character(len=:), allocatable :: value
        integer :: line = 0
        !> Number of values after expanding repeat counts; 0 if the value is empty.
        integer :: n_values = 0
        !> Position in the text of the first and last characters of the value (without a
        !> trailing comma; value_last = value_first - 1 if empty): where rs_io_sweep edits it.
        integer :: value_first = 0
        integer :: value_last = -1
    end type assignment_t

    !> One `&group ... /` occurrence.
    type :: group_chunk_t
        character(len=:), allocatable :: name
        integer :: line = 0
        type(assignment_t), allocatable :: assignments(:)
        !> Position in the text of its "&", of the last character of its name and of its
        !> closing "/" (or of the "d" of "&end").
        integer :: first = 0
        integer :: name_end = 0
        integer :: last = 0
    end type group_chunk_t

    character(len=*), parameter :: blanks = ' ' // achar(9) // achar(10) // achar(13)

contains

    !> Split `text` (the contents of `file`) into group chunks; problems go to `errors`.
    subroutine split_namelist(text, file, chunks, errors)
        character(len=*), intent(in) :: text, file
        type(group_chunk_t), allocatable, intent(out) :: chunks(:)
        type(error_list_t), intent(inout) :: errors
        ! Allocatable, not automatic: a scene may be larger than the stack (issue 21 item 17).
        character(len=:), allocatable :: clean
        integer, allocatable :: line_of(:)
        integer :: p, n, name_end, body_end, reported_line, n_chunks
        type(group_chunk_t) :: chunk
        logical :: unterminated_string

        allocate(chunks(0))
        call check_utf8(text, file, errors)
        n = len(text)
        allocate(character(len=n) :: clean)
        allocate(line_of(n))
        call strip_comments(text, clean, line_of, unterminated_string)
        if (unterminated_string) then
            call errors%add(file // ': a quoted string is not closed before the end of the file')
            return
        end if
        n_chunks = 0
        p = 1
        reported_line = 0
        do while (p <= n)
            if (index(blanks, clean(p:p)) > 0) then
                p = p + 1
                cycle
            end if
            if (clean(p:p) == '&') then
                name_end = p
                do while (name_end < n)
                    if (.not. is_name_char(clean(name_end + 1:name_end + 1))) exit
                    name_end = name_end + 1
                end do
                if (name_end == p) then
                    call errors%add(file // ':' // str(line_of(p)) // ': a group name must follow "&"')
                    p = p + 1
                    cycle
                end if
                chunk%name = to_lower(clean(p + 1:name_end))
                chunk%line = line_of(p)
                chunk%first = p
                chunk%name_end = name_end
                body_end = find_group_end(clean, name_end + 1)
                if (body_end == 0) then
                    call errors%add(file // ':' // str(chunk%line) // ': &' // chunk%name // &
                        ' is not closed by "/"')
                    return
                end if
                if (body_end < 0) then
                    call errors%add(file // ':' // str(chunk%line) // ': &' // chunk%name // &
                        ' is not closed by "/" before the next group (line ' // &
                        str(line_of(-body_end)) // ')')
                    p = -body_end
                    cycle
                end if
                call split_assignments(clean, line_of, name_end + 1, body_end - 1, file, chunk, errors)
                chunk%last = body_end
                if (clean(body_end:body_end) == '&') chunk%last = body_end + 3   ! "&end"
                call append_chunk(chunks, n_chunks, chunk)
                p = chunk%last + 1
            else
                if (line_of(p) /= reported_line) then
                    call errors%add(file // ':' // str(line_of(p)) // ': text outside a namelist group: "' // &
                        snippet(clean, p) // '" (a group starts with &name and ends with /)')
                    reported_line = line_of(p)
                end if
                p = p + 1
            end if
        end do
        call shrink_chunks(chunks, n_chunks)
    end subroutine split_namelist

    !> Report every line of `text` that is not valid UTF-8, with its first bad byte (position
    !> in the file and on the line, and its value). The scene text is stored in the result file
    !> as a UTF-8 string (/input/text) that h5py and other readers decode: a Latin-1 "é" there
    !> made output.md's own recipe fail (issue 21 item 19). Rejected rather than escaped, so
    !> that the stored text is the file as written.
    subroutine check_utf8(text, file, errors)
        character(len=*), intent(in) :: text, file
        type(error_list_t), intent(inout) :: errors
        integer :: i, line, line_start, length, reported_line
        character(len=2) :: hex
        i = 1
        line = 1
        line_start = 1
        reported_line = 0
        do while (i <= len(text))
            length = utf8_sequence_length(text, i)
            if (length == 0) then
                if (line /= reported_line) then
                    write(hex, '(z2.2)') iachar(text(i:i))
                    call errors%add(file // ':' // str(line) // ': byte ' // str(i) // &
                        ' (column ' // str(i - line_start + 1) // ', value 0x' // hex // &
                        ') is not valid UTF-8: scene files must be ' // &
                        'UTF-8 (ASCII is) since the scene is stored as UTF-8 text in the ' // &
                        'result file; re-encode it, e.g. iconv -f latin1 -t utf-8')
                    reported_line = line
                end if
                length = 1
            end if
            if (text(i:i) == achar(10)) then
                line = line + 1
                line_start = i + 1
            end if
            i = i + length
        end do
    end subroutine check_utf8

    !> Length (1 to 4) of the well-formed UTF-8 sequence starting at text(i:i) (Unicode 15,
    !> table 3-7: no overlong forms, no surrogates, nothing above U+10FFFF); 0 if ill-formed.
    pure integer function utf8_sequence_length(text, i) result(length)
        character(len=*), intent(in) :: text
        integer, intent(in) :: i
        integer :: lead, second_low, second_high, k
        lead = iachar(text(i:i))
        length = 0
        second_low = 128
        second_high = 191
        select case (lead)
        case (0:127)
            length = 1
            return
        case (194:223)
            length = 2
        case (224)
            length = 3
            second_low = 160
        case (225:236, 238:239)
            length = 3
        case (237)
            length = 3
            second_high = 159
        case (240)
            length = 4
            second_low = 144
        case (241:243)
            length = 4
        case (244)
            length = 4
            second_high = 143
        case default
            return
        end select
        if (i + length - 1 > len(text)) then
            length = 0
            return
        end if
        do k = 1, length - 1
            associate (byte => iachar(text(i + k:i + k)))
                if (k == 1) then
                    if (byte < second_low .or. byte > second_high) length = 0
                else
                    if (byte < 128 .or. byte > 191) length = 0
                end if
            end associate
            if (length == 0) return
        end do
    end function utf8_sequence_length

    !> Append `chunk` as chunks(n + 1), the capacity doubling when full: reading stays linear
    !> in the number of groups (issue 21 item 17: 4,000 &load groups took 45 s when every
    !> group copied all the groups before it).
    subroutine append_chunk(chunks, n, chunk)
        type(group_chunk_t), allocatable, intent(inout) :: chunks(:)
        integer, intent(inout) :: n
        type(group_chunk_t), intent(in) :: chunk
        type(group_chunk_t), allocatable :: grown(:)
        integer :: k
        if (n == size(chunks)) then
            allocate(grown(max(16, 2 * n)))
            do k = 1, n
                call move_chunk(chunks(k), grown(k))
            end do
            call move_alloc(grown, chunks)
        end if
        n = n + 1
        chunks(n) = chunk
    end subroutine append_chunk

    !> Drop the unused capacity past chunks(n).
    subroutine shrink_chunks(chunks, n)
        type(group_chunk_t), allocatable, intent(inout) :: chunks(:)
        integer, intent(in) :: n
        type(group_chunk_t), allocatable :: kept(:)
        integer :: k
        if (n == size(chunks)) return
        allocate(kept(n))
        do k = 1, n
            call move_chunk(chunks(k), kept(k))
        end do
        call move_alloc(kept, chunks)
    end subroutine shrink_chunks

    !> Move a chunk without copying its assignments.
    subroutine move_chunk(from, to)
        type(group_chunk_t), intent(inout) :: from
        type(group_chunk_t), intent(inout) :: to
        call move_alloc(from%name, to%name)
        call move_alloc(from%assignments, to%assignments)
        to%line = from%line
        to%first = from%first
        to%name_end = from%name_end
        to%last = from%last
    end subroutine move_chunk

    !> Blank out comments (keeping newlines) and note the line of every character.
    subroutine strip_comments(text, clean, line_of, unterminated_string)
        character(len=*), intent(in) :: text
        character(len=*), intent(out) :: clean
        integer, intent(out) :: line_of(:)
        logical, intent(out) :: unterminated_string
        character :: quote, c
        logical :: in_comment
        integer :: i, line
        clean = text
        quote = ' '
        in_comment = .false.
        line = 1
        do i = 1, len(text)
            c = text(i:i)
            line_of(i) = line
            if (c == achar(10)) then
                line = line + 1
                in_comment = .false.
                cycle
            end if
            if (in_comment) then
                clean(i:i) = ' '
            else if (quote /= ' ') then
                if (c == quote) quote = ' '
            else if (c == '"' .or. c == "'") then
                quote = c
            else if (c == '!') then
                in_comment = .true.
                clean(i:i) = ' '
            end if
        end do
        unterminated_string = quote /= ' '
    end subroutine strip_comments

    !> Position of the "/" (or of "&end") closing the group whose body starts at `from`; 0 if
    !> the text ends first, minus the position of the next "&group" if that comes first.
    pure integer function find_group_end(clean, from) result(at)
        character(len=*), intent(in) :: clean
        integer, intent(in) :: from
        character :: quote
        integer :: i
        quote = ' '
        at = 0
        do i = from, len(clean)
            if (quote /= ' ') then
                if (clean(i:i) == quote) quote = ' '
            else if (clean(i:i) == '"' .or. clean(i:i) == "'") then
                quote = clean(i:i)
            else if (clean(i:i) == '/') then
                at = i
                return
            else if (clean(i:i) == '&') then
                ! "&end" closes the group (old style); any other "&name" starts the next group,
                ! so this one was never closed: returned as -i.
                at = -i
                if (i + 3 <= len(clean)) then
                    if (to_lower(clean(i:i + 3)) == '&end') at = i
                end if
                if (i + 4 <= len(clean) .and. at > 0) then
                    if (is_name_char(clean(i + 4:i + 4))) at = -i
                end if
                return
            end if
        end do
    end function find_group_end

    !> Split the body clean(first:last) of `chunk` into its assignments.
    subroutine split_assignments(clean, line_of, first, last, file, chunk, errors)
        character(len=*), intent(in) :: clean
        integer, intent(in) :: line_of(:), first, last
        character(len=*), intent(in) :: file
        type(group_chunk_t), intent(inout) :: chunk
        type(error_list_t), intent(inout) :: errors
        integer, allocatable :: equals(:), starts(:)
        integer :: i, k, depth, j, value_end, n_equals, n_kept, pass
        character :: quote
        type(assignment_t) :: a
        type(assignment_t), allocatable :: kept(:)

        if (allocated(chunk%assignments)) deallocate(chunk%assignments)
        ! Two passes, counting and then recording the "=", instead of growing the list by one
        ! per "=" (quadratic in the assignments of a group).
        allocate(equals(0))
        do pass = 1, 2
            n_equals = 0
            quote = ' '
            depth = 0
            do i = first, last
                if (quote /= ' ') then
                    if (clean(i:i) == quote) quote = ' '
                else if (clean(i:i) == '"' .or. clean(i:i) == "'") then
                    quote = clean(i:i)
                else if (clean(i:i) == '(') then
                    depth = depth + 1
                else if (clean(i:i) == ')') then
                    depth = depth - 1
                else if (clean(i:i) == '=' .and. depth == 0) then
                    n_equals = n_equals + 1
                    if (pass == 2) equals(n_equals) = i
                end if
            end do
            if (pass == 1) then
                deallocate(equals)
                allocate(equals(n_equals))
            end if
        end do
        allocate(chunk%assignments(size(equals)))
        n_kept = 0

        allocate(starts(size(equals)))
        do k = 1, size(equals)
            starts(k) = target_start(clean, first, equals(k) - 1)
        end do
        ! Whatever precedes the first target must be blank (or separators).
        j = last
        if (size(equals) > 0) j = starts(1) - 1
        if (verify(clean(first:j), blanks // ',') > 0) then
            i = first - 1 + verify(clean(first:j), blanks // ',')
            call errors%add(file // ':' // str(line_of(i)) // ': &' // chunk%name // &
                ': expected "name = value", found "' // snippet(clean, i) // '"')
        end if

        do k = 1, size(equals)
            if (starts(k) >= equals(k)) then
                call errors%add(file // ':' // str(line_of(equals(k))) // ': &' // chunk%name // &
                    ': "=" without a variable name before it')
                cycle
            end if
            a%target = remove_blanks(clean(starts(k):equals(k) - 1))
            if (len(a%target) == 0) then
                call errors%add(file // ':' // str(line_of(equals(k))) // ': &' // chunk%name // &
                    ': "=" without a variable name before it')
                cycle
            end if
            if (.not. is_letter(a%target(1:1))) then
                call errors%add(file // ':' // str(line_of(equals(k))) // ': &' // chunk%name // &
                    ': "=" without a variable name before it (found "' // a%target // '")')
                cycle
            end if
            a%subscripted = index(a%target, '(') > 0
            if (a%subscripted) then
                a%name = to_lower(a%target(1:index(a%target, '(') - 1))
            else
                a%name = to_lower(a%target)
            end if
            a%line = line_of(starts(k))
            value_end = last
            if (k < size(equals)) value_end = starts(k + 1) - 1
            call value_span(clean, equals(k) + 1, value_end, a%value_first, a%value_last)
            a%value = one_line(clean(equals(k) + 1:value_end))
            a%n_values = count_values(a%value)
            n_kept = n_kept + 1
            chunk%assignments(n_kept) = a
        end do
        if (n_kept < size(chunk%assignments)) then
            kept = chunk%assignments(1:n_kept)
            call move_alloc(kept, chunk%assignments)
        end if
    end subroutine split_assignments

    !> First and last non-blank characters of clean(from:to) without one trailing comma, as
    !> one_line keeps them; last = first - 1 if there are none.
    pure subroutine value_span(clean, from, to, first, last)
        character(len=*), intent(in) :: clean
        integer, intent(in) :: from, to
        integer, intent(out) :: first, last
        first = from
        do while (first <= to)
            if (index(blanks, clean(first:first)) == 0) exit
            first = first + 1
        end do
        last = to
        do while (last >= first)
            if (index(blanks, clean(last:last)) == 0) exit
            last = last - 1
        end do
        if (last >= first) then
            if (clean(last:last) == ',') then
                last = last - 1
                do while (last >= first)
                    if (index(blanks, clean(last:last)) == 0) exit
                    last = last - 1
                end do
            end if
        end if
        if (last < first) last = first - 1
    end subroutine value_span

    !> Start of the variable name that ends just before position `last` + 1 (skipping blanks
    !> and one subscript in parentheses).
    pure integer function target_start(clean, first, last) result(at)
        character(len=*), intent(in) :: clean
        integer, intent(in) :: first, last
        integer :: i, depth
        i = last
        do while (i >= first)
            if (index(blanks, clean(i:i)) == 0) exit
            i = i - 1
        end do
        if (i >= first) then
            if (clean(i:i) == ')') then
                depth = 0
                do while (i >= first)
                    if (clean(i:i) == ')') depth = depth + 1
                    if (clean(i:i) == '(') depth = depth - 1
                    i = i - 1
                    if (depth == 0) exit
                end do
                do while (i >= first)
                    if (index(blanks, clean(i:i)) == 0) exit
                    i = i - 1
                end do
            end if
        end if
        do while (i >= first)
            if (.not. is_name_char(clean(i:i))) exit
            i = i - 1
        end do
        at = i + 1
    end function target_start

    !> Number of values in a value text: separators are commas and blanks outside quotes, and a
    !> token r*v counts r times.
    pure integer function count_values(value) result(n)
        character(len=*), intent(in) :: value
        integer :: i, token_start, repeat, star, ios
        character :: quote
        logical :: in_token
        n = 0
        quote = ' '
        in_token = .false.
        token_start = 1
        do i = 1, len(value) + 1
            if (i <= len(value)) then
                if (quote /= ' ') then
                    if (value(i:i) == quote) quote = ' '
                    cycle
                end if
                if (value(i:i) == '"' .or. value(i:i) == "'") then
                    quote = value(i:i)
                    if (.not. in_token) then
                        in_token = .true.
                        token_start = i
                    end if
                    cycle
                end if
                if (value(i:i) /= ',' .and. value(i:i) /= ' ') then
                    if (.not. in_token) then
                        in_token = .true.
                        token_start = i
                    end if
                    cycle
                end if
            end if
            if (in_token) then
                star = index(value(token_start:i - 1), '*')
                repeat = 1
                if (star > 1 .and. value(token_start:token_start) /= '"' .and. &
                        value(token_start:token_start) /= "'") then
                    read(value(token_start:token_start + star - 2), *, iostat=ios) repeat
                    if (ios /= 0) repeat = 1
                end if
                n = n + repeat
                in_token = .false.
            end if
        end do
    end function count_values

    pure logical function is_letter(c)
        character, intent(in) :: c
        is_letter = (c >= 'a' .and. c <= 'z') .or. (c >= 'A' .and. c <= 'Z')
    end function is_letter

    pure logical function is_name_char(c)
        character, intent(in) :: c
        is_name_char = (c >= 'a' .and. c <= 'z') .or. (c >= 'A' .and. c <= 'Z') .or. &
            (c >= '0' .and. c <= '9') .or. c == '_' .or. c == '%'
    end function is_name_char

    pure function remove_blanks(text) result(out)
        character(len=*), intent(in) :: text
        character(len=:), allocatable :: out
        integer :: i, n
        allocate(character(len=len(text)) :: out)
        n = 0
        do i = 1, len(text)
            if (index(blanks, text(i:i)) > 0) cycle
            n = n + 1
            out(n:n) = text(i:i)
        end do
        out = out(1:n)
    end function remove_blanks

    !> Newlines and tabs to blanks, outer blanks and one trailing comma removed.
    pure function one_line(text) result(out)
        character(len=*), intent(in) :: text
        character(len=:), allocatable :: out
        integer :: i
        character(len=:), allocatable :: work
        work = text
        do i = 1, len(work)
            if (index(blanks, work(i:i)) > 0) work(i:i) = ' '
        end do
        out = trim(adjustl(work))
        if (len(out) > 0) then
            if (out(len(out):len(out)) == ',') out = trim(out(1:len(out) - 1))
        end if
    end function one_line

    !> Up to 30 characters of the line at position `at`, for messages.
    pure function snippet(text, at) result(out)
        character(len=*), intent(in) :: text
        integer, intent(in) :: at
        character(len=:), allocatable :: out
        integer :: last
        last = at
        do while (last < len(text) .and. last - at < 30)
            if (text(last + 1:last + 1) == achar(10)) exit
            last = last + 1
        end do
        out = trim(text(at:last))
    end function snippet

end module rs_io_namelist_lexer
