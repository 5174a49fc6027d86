!> Systems of units a scene may be written in (&run units). rodsolve's equations hold in any
!> consistent system, so the numbers are used as given; the system only changes the unit names
!> shown to people (--check-input, the input reference, later the output's `unit` attributes).
!>
!> | system       | length | mass  | time | force | stress, pressure | energy |
!> |--------------|--------|-------|------|-------|------------------|--------|
!> | `si`         | m      | kg    | s    | N     | Pa               | J      |
!> | `mm_tonne_s` | mm     | tonne | s    | N     | MPa              | mJ     |
!> | `mm_kg_ms`   | mm     | kg    | ms   | kN    | GPa              | J      |
!> | `mm_g_ms`    | mm     | g     | ms   | N     | MPa              | mJ     |
!>
!> Each is consistent: force = mass length / time^2, stress = force / length^2, energy = force
!> length (e.g. tonne mm / s^2 = 1e3 kg 1e-3 m / s^2 = 1 N). Angles are radians in every system.
module rs_model_units
    implicit none
    private

    public :: unit_in_system, is_unit_system

    !> The systems, '|'-separated (the allowed values of &run units).
    character(len=*), parameter, public :: unit_systems = 'si|mm_tonne_s|mm_kg_ms|mm_g_ms'

    !> The SI base symbols that a system renames, and their names in each system (same order).
    character(len=2), parameter :: si_symbols(6) = [character(len=2) :: 'm', 'kg', 's', 'N', 'Pa', 'J']

contains

    !> True if `system` is one of unit_systems.
    pure logical function is_unit_system(system)
        character(len=*), intent(in) :: system
        is_unit_system = len_trim(system) > 0 .and. &
            index('|' // unit_systems // '|', '|' // trim(system) // '|') > 0
    end function is_unit_system

    !> The SI unit text `si_unit` (as in docs/user/input.md: 'm', 'kg/m^3', 'N m^2', 'N or N/m',
    !> 'rad/s', '-') written in `system`: every SI symbol m, kg, s, N, Pa, J is renamed, the
    !> rest (exponents, '/', blanks, 'or', 'rad', '-') is kept. An unknown system keeps SI.
    pure function unit_in_system(si_unit, system) result(text)
        character(len=*), intent(in) :: si_unit, system
        character(len=:), allocatable :: text
        integer :: i, j, k
        text = ''
        i = 1
        do while (i <= len_trim(si_unit))
            if (.not. is_letter(si_unit(i:i))) then
                text = text // si_unit(i:i)
                i = i + 1
                cycle
            end if
            j = i
            do while (j < len_trim(si_unit))
                if (.not. is_letter(si_unit(j + 1:j + 1))) exit
                j = j + 1
            end do
            k = findloc(si_symbols, si_unit(i:j), dim=1)
            if (k > 0) then
                text = text // renamed(k)
            else
                text = text // si_unit(i:j)
            end if
            i = j + 1
        end do
    contains
        pure function renamed(symbol) result(name)
            integer, intent(in) :: symbol
            character(len=:), allocatable :: name
            character(len=5) :: names(6)
            select case (trim(system))
            case ('mm_tonne_s')
                names = [character(len=5) :: 'mm', 'tonne', 's', 'N', 'MPa', 'mJ']
            case ('mm_kg_ms')
                names = [character(len=5) :: 'mm', 'kg', 'ms', 'kN', 'GPa', 'J']
            case ('mm_g_ms')
                names = [character(len=5) :: 'mm', 'g', 'ms', 'N', 'MPa', 'mJ']
            case default
                names = [character(len=5) :: 'm', 'kg', 's', 'N', 'Pa', 'J']
            end select
            name = trim(names(symbol))
        end function renamed
    end function unit_in_system

    pure logical function is_letter(c)
        character, intent(in) :: c
        is_letter = (c >= 'a' .and. c <= 'z') .or. (c >= 'A' .and. c <= 'Z')
    end function is_letter

end module rs_model_units
