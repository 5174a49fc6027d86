!> The first difference between two resolved scene texts (rs_io_scene_writer): a restart must
!> continue the scene its checkpoint was computed with (issue 21 item 7; docs/user/output.md,
!> "Writing, flushes, a killed run, restarts"). The resolved text names every variable with
!> its value, defaults and derived values included, so comparing it compares the scenes.
module rs_io_scene_diff
    implicit none
    private

    public :: first_scene_difference

    !> One `name = value` line of a resolved scene: its group, the group's ordinal among the
    !> groups of that name (the 2nd &rod is 2), the rod or object name if the group has one.
    type :: entry_t
        character(len=:), allocatable :: group, label, name, value
        integer :: ordinal = 0
    end type entry_t

contains

    !> '' when `before` (what a file stored) and `now` give every variable the same value,
    !> apart from the variables in `free` ('group%name', e.g. 'time%t_end'); otherwise one
    !> sentence naming the first variable that differs, with both values. `stored_as` names
    !> `before` in it (default "the checkpoint's scene").
    function first_scene_difference(before, now, free, stored_as) result(message)
        character(len=*), intent(in) :: before, now
        character(len=*), intent(in) :: free(:)
        character(len=*), intent(in), optional :: stored_as
        character(len=:), allocatable :: message, there
        type(entry_t), allocatable :: a(:), b(:)
        integer :: i, j
        message = ''
        there = 'the checkpoint''s scene'
        if (present(stored_as)) there = stored_as
        call parse(before, a)
        call parse(now, b)
        do i = 1, size(a)
            if (is_free(a(i))) cycle
            j = find(b, a(i))
            if (j == 0) then
                message = where_(a(i)) // ' = ' // a(i)%value // ' in ' // there // &
                    ' is not in this scene'
                return
            end if
            if (b(j)%value /= a(i)%value) then
                message = where_(a(i)) // ': ' // a(i)%value // ' in ' // there // ', ' // &
                    b(j)%value // ' in this one'
                return
            end if
        end do
        do j = 1, size(b)
            if (is_free(b(j))) cycle
            if (find(a, b(j)) /= 0) cycle
            message = where_(b(j)) // ' = ' // b(j)%value // ' in this scene is not in ' // there
            return
        end do
    contains
        logical function is_free(e)
            type(entry_t), intent(in) :: e
            integer :: k
            is_free = .false.
            do k = 1, size(free)
                if (trim(free(k)) == e%group // '%' // e%name) is_free = .true.
            end do
        end function is_free
    end function first_scene_difference

    !> "&rod 'arm' EA" or "&load 2 force": where an entry is, for messages.
    function where_(e) result(text)
        type(entry_t), intent(in) :: e
        character(len=:), allocatable :: text
        character(len=12) :: number
        if (len(e%label) > 0) then
            text = '&' // e%group // ' ' // e%label // ' ' // e%name
        else if (e%ordinal > 1) then
            write(number, '(i0)') e%ordinal
            text = '&' // e%group // ' ' // trim(number) // ' ' // e%name
        else
            text = '&' // e%group // ' ' // e%name
        end if
    end function where_

    !> The index in `list` of the entry with `e`'s group, ordinal and name; 0 if none.
    integer function find(list, e)
        type(entry_t), intent(in) :: list(:), e
        integer :: k
        find = 0
        do k = 1, size(list)
            if (list(k)%ordinal /= e%ordinal) cycle
            if (list(k)%name /= e%name .or. list(k)%group /= e%group) cycle
            find = k
            return
        end do
    end function find

    !> The `name = value` lines of a resolved scene text; comment lines (starting with '!',
    !> the values a section determines among them) are left out.
    subroutine parse(text, entries)
        character(len=*), intent(in) :: text
        type(entry_t), allocatable, intent(out) :: entries(:)
        type(entry_t), allocatable :: grown(:)
        character(len=:), allocatable :: line, group, label
        character(len=32), allocatable :: groups(:)
        integer :: start, eol, eq, n, ordinal, first
        allocate(entries(64), groups(0))
        n = 0
        group = ''
        label = ''
        ordinal = 0
        first = 1
        start = 1
        do while (start <= len(text))
            eol = index(text(start:), new_line('a'))
            if (eol == 0) eol = len(text) - start + 2
            line = trim(adjustl(text(start:start + eol - 2)))
            start = start + eol
            if (len(line) == 0) cycle
            if (line(1:1) == '!') cycle
            if (line(1:1) == '&') then
                group = trim(line(2:))
                label = ''
                groups = [character(len=32) :: groups, group]
                ordinal = count(groups == group)
                first = n + 1
                cycle
            end if
            if (line(1:1) == '/') cycle
            eq = index(line, ' = ')
            if (eq == 0) cycle
            if (n == size(entries)) then
                allocate(grown(2 * size(entries)))
                grown(1:n) = entries(1:n)
                call move_alloc(grown, entries)
            end if
            n = n + 1
            entries(n)%group = group
            entries(n)%ordinal = ordinal
            entries(n)%name = line(1:eq - 1)
            entries(n)%value = line(eq + 3:)
            entries(n)%label = ''
            ! A named group (a rod, a plate) is named by its first line: label its entries.
            if (entries(n)%name == 'name' .and. n == first) then
                label = entries(n)%value
                entries(n)%label = label
            else if (len(label) > 0) then
                entries(n)%label = label
            end if
        end do
        entries = entries(1:n)
    end subroutine parse

end module rs_io_scene_diff
