#include "rs_assert.h"
!> Unit tests of rs_model_units: every unit string of the input reference in each system
!> (the mapping of docs/user/input.md, "Units"), consistency of each system (force = mass
!> length / time^2, stress = force / length^2, energy = force length, checked through the SI
!> factors of its base units), and the list of systems.
module rs_test_model_units
    use rs_core_kinds, only: rk
    use rs_test_assert, only: run_test, assert_true, assert_equal, assert_close
    use rs_model_units, only: unit_in_system, is_unit_system, unit_systems
    implicit none
    private

    public :: run_all_tests

contains

    subroutine run_all_tests()
        call run_test('si_unchanged', test_si_unchanged)
        call run_test('mm_tonne_s', test_mm_tonne_s)
        call run_test('mm_kg_ms', test_mm_kg_ms)
        call run_test('mm_g_ms', test_mm_g_ms)
        call run_test('systems_are_consistent', test_systems_consistent)
        call run_test('system_names', test_system_names)
    end subroutine run_all_tests

    subroutine test_si_unchanged()
        character(len=12), parameter :: units(8) = [character(len=12) :: 'm', 'kg/m^3', 'N m^2', &
            'N or N/m', 'rad/s', '-', 'm/s^2', 'kg m']
        integer :: i
        do i = 1, size(units)
            CHECK_EQUAL(unit_in_system(trim(units(i)), 'si'), trim(units(i)), 'si: ' // trim(units(i)))
        end do
    end subroutine test_si_unchanged

    subroutine test_mm_tonne_s()
        CHECK_EQUAL(unit_in_system('m', 'mm_tonne_s'), 'mm', 'length')
        CHECK_EQUAL(unit_in_system('Pa', 'mm_tonne_s'), 'MPa', 'stress')
        CHECK_EQUAL(unit_in_system('kg/m^3', 'mm_tonne_s'), 'tonne/mm^3', 'density')
        CHECK_EQUAL(unit_in_system('N m^2', 'mm_tonne_s'), 'N mm^2', 'bending stiffness')
        CHECK_EQUAL(unit_in_system('N m or N', 'mm_tonne_s'), 'N mm or N', 'moment')
        CHECK_EQUAL(unit_in_system('kg m', 'mm_tonne_s'), 'tonne mm', 'inertia per length')
        CHECK_EQUAL(unit_in_system('rad/s', 'mm_tonne_s'), 'rad/s', 'angular velocity')
        CHECK_EQUAL(unit_in_system('m/s^2', 'mm_tonne_s'), 'mm/s^2', 'acceleration')
        CHECK_EQUAL(unit_in_system('-', 'mm_tonne_s'), '-', 'dimensionless')
        CHECK_EQUAL(unit_in_system('J', 'mm_tonne_s'), 'mJ', 'energy')
    end subroutine test_mm_tonne_s

    subroutine test_mm_kg_ms()
        CHECK_EQUAL(unit_in_system('N', 'mm_kg_ms'), 'kN', 'force')
        CHECK_EQUAL(unit_in_system('Pa', 'mm_kg_ms'), 'GPa', 'stress')
        CHECK_EQUAL(unit_in_system('m/s', 'mm_kg_ms'), 'mm/ms', 'velocity')
        CHECK_EQUAL(unit_in_system('rad/s', 'mm_kg_ms'), 'rad/ms', 'angular velocity')
        CHECK_EQUAL(unit_in_system('s', 'mm_kg_ms'), 'ms', 'time')
    end subroutine test_mm_kg_ms

    subroutine test_mm_g_ms()
        CHECK_EQUAL(unit_in_system('kg/m', 'mm_g_ms'), 'g/mm', 'mass per length')
        CHECK_EQUAL(unit_in_system('N or N/m', 'mm_g_ms'), 'N or N/mm', 'force or per length')
        CHECK_EQUAL(unit_in_system('Pa', 'mm_g_ms'), 'MPa', 'stress')
    end subroutine test_mm_g_ms

    ! SI factors of (length, mass, time) and of the names the module gives force, stress and
    ! energy: a system is consistent when those names are the derived units.
    subroutine test_systems_consistent()
        call check('mm_tonne_s', 1.0e-3_rk, 1.0e3_rk, 1.0_rk, 'N', 'MPa', 'mJ')
        call check('mm_kg_ms', 1.0e-3_rk, 1.0_rk, 1.0e-3_rk, 'kN', 'GPa', 'J')
        call check('mm_g_ms', 1.0e-3_rk, 1.0e-3_rk, 1.0e-3_rk, 'N', 'MPa', 'mJ')
        call check('si', 1.0_rk, 1.0_rk, 1.0_rk, 'N', 'Pa', 'J')
    contains
        subroutine check(system, length, mass, time, force, stress, energy)
            character(len=*), intent(in) :: system, force, stress, energy
            real(rk), intent(in) :: length, mass, time
            real(rk) :: f
            f = mass * length / time**2
            CHECK_EQUAL(unit_in_system('N', system), force, system // ': force name')
            CHECK_CLOSE(f, factor(force), 0.0_rk, 1.0e-12_rk, system // ': force = mass length / time^2')
            CHECK_EQUAL(unit_in_system('Pa', system), stress, system // ': stress name')
            CHECK_CLOSE(f / length**2, factor(stress), 0.0_rk, 1.0e-12_rk, system // ': stress')
            CHECK_EQUAL(unit_in_system('J', system), energy, system // ': energy name')
            CHECK_CLOSE(f * length, factor(energy), 0.0_rk, 1.0e-12_rk, system // ': energy')
        end subroutine check

        real(rk) function factor(name)
            character(len=*), intent(in) :: name
            select case (name)
            case ('N', 'Pa', 'J')
                factor = 1.0_rk
            case ('kN')
                factor = 1.0e3_rk
            case ('MPa')
                factor = 1.0e6_rk
            case ('GPa')
                factor = 1.0e9_rk
            case ('mJ')
                factor = 1.0e-3_rk
            case default
                factor = -1.0_rk
            end select
        end function factor
    end subroutine test_systems_consistent

    subroutine test_system_names()
        CHECK_TRUE(is_unit_system('si'), 'si')
        CHECK_TRUE(is_unit_system('mm_tonne_s'), 'mm_tonne_s')
        CHECK_TRUE(.not. is_unit_system('mm'), 'a prefix is not a system')
        CHECK_TRUE(.not. is_unit_system(''), 'blank')
        CHECK_EQUAL(unit_systems, 'si|mm_tonne_s|mm_kg_ms|mm_g_ms', 'the allowed values of &run units')
    end subroutine test_system_names

end module rs_test_model_units

program test_model_units
    use rs_test_model_units, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_model_units
