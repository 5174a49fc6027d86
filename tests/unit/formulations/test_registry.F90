#include "rs_assert.h"
!> Unit tests of rs_formulations_registry and its descriptors (issue 22 item 4): every
!> formulation has a unique name, an available capability row naming it, a constructor that
!> builds an object and plan lines; exactly one default (3D) and one planar choice of 'auto';
!> the &rod variables a descriptor claims as its own are &rod variables of the input spec that
!> the capability check can read (rs_io_input_capability_check: a claim it could not read
!> would never be enforced); the factory builds through the descriptors and lists the names on
!> an unknown one; the bundle of a coupled system exists only where the descriptor says so.
module rs_test_formulations_registry
    use rs_test_assert, only: run_test, assert_true, assert_equal
    use rs_core_error, only: error_t
    use rs_core_strings, only: split_list
    use rs_model_scene, only: scene_t
    use rs_model_capabilities, only: capability_t
    use rs_formulations_formulation, only: rod_formulation_t
    use rs_formulations_descriptor, only: formulation_descriptor_t
    use rs_formulations_registry, only: formulation_descriptors, descriptor_of, capability_of, &
        formulation_names, available_formulations, default_formulation, auto_planar_formulation, &
        is_bundle
    use rs_formulations_factory, only: create_formulation
    use rs_io_input_spec, only: group_spec_t, input_groups, find_group, find_variable
    use rs_io_input_capability_check, only: rod_variable_given
    implicit none
    private

    public :: run_all_tests

contains

    !> Run every test of this file through rs_test_assert.
    subroutine run_all_tests()
        call run_test('descriptors_complete', test_descriptors_complete)
        call run_test('one_default_one_planar_choice', test_one_default_one_planar_choice)
        call run_test('own_rod_variables_known', test_own_rod_variables_known)
        call run_test('factory_through_descriptors', test_factory_through_descriptors)
        call run_test('bundle_where_described', test_bundle_where_described)
    end subroutine run_all_tests

    !> Names unique and listed by formulation_names and available_formulations in registry
    !> order; each row available and naming its formulation; constructor and plan lines set.
    subroutine test_descriptors_complete()
        type(formulation_descriptor_t), allocatable :: list(:)
        type(formulation_descriptor_t) :: d
        character(len=32), allocatable :: names(:)
        character(len=:), allocatable :: joined, name
        type(capability_t) :: row
        class(rod_formulation_t), allocatable :: rod
        integer :: k
        list = formulation_descriptors()
        names = formulation_names()
        CHECK_TRUE(size(list) >= 2, 'several formulations')
        CHECK_EQUAL(size(names), size(list), 'one name per descriptor')
        joined = ''
        do k = 1, size(list)
            name = trim(list(k)%name)
            CHECK_TRUE(len(name) > 0, 'named')
            CHECK_EQUAL(count(names == list(k)%name), 1, 'listed once: ' // name)
            CHECK_EQUAL(trim(names(k)), name, 'formulation_names in registry order')
            CHECK_EQUAL(trim(list(k)%capability%formulation), name, 'row names it: ' // name)
            CHECK_TRUE(list(k)%capability%available, 'available: ' // name)
            CHECK_TRUE(associated(list(k)%create), 'constructor: ' // name)
            CHECK_TRUE(associated(list(k)%plan_lines), 'plan lines: ' // name)
            CHECK_TRUE(descriptor_of(name, d), 'found by name: ' // name)
            CHECK_EQUAL(trim(d%name), name, 'descriptor_of returns it: ' // name)
            row = capability_of(name)
            CHECK_EQUAL(trim(row%formulation), name, 'capability_of: ' // name)
            if (associated(list(k)%create)) then
                call list(k)%create(rod)
                CHECK_TRUE(allocated(rod), 'constructor builds: ' // name)
                if (allocated(rod)) deallocate(rod)
            end if
            if (k > 1) joined = joined // ', '
            joined = joined // name
        end do
        CHECK_EQUAL(available_formulations(), joined, 'available_formulations')
        CHECK_TRUE(.not. descriptor_of('auto', d), 'auto is no formulation')
        row = capability_of('auto')
        CHECK_TRUE(.not. row%available, 'auto has no row')
    end subroutine test_descriptors_complete

    !> 'auto' and &run formulation_default need exactly one default (3D) and one planar choice.
    subroutine test_one_default_one_planar_choice()
        type(formulation_descriptor_t), allocatable :: list(:)
        type(capability_t) :: row
        list = formulation_descriptors()
        CHECK_EQUAL(count(list%default_choice), 1, 'one default formulation')
        CHECK_EQUAL(count(list%auto_planar_choice), 1, 'one planar choice of auto')
        row = capability_of(default_formulation())
        CHECK_TRUE(.not. row%planar, 'the default is 3D')
        row = capability_of(auto_planar_formulation())
        CHECK_TRUE(row%planar, 'the planar choice is planar')
    end subroutine test_one_default_one_planar_choice

    !> Every variable in a descriptor's own_rod_variables is a &rod variable of the input spec
    !> and one that rod_variable_given can read; no variable is claimed twice.
    subroutine test_own_rod_variables_known()
        type(formulation_descriptor_t), allocatable :: list(:)
        type(group_spec_t), allocatable :: groups(:)
        character(len=:), allocatable :: claimed, variable, what
        type(scene_t) :: scene
        logical :: known, given
        character(len=32), allocatable :: variables(:)
        integer :: k, v, rod_group
        groups = input_groups()
        rod_group = find_group(groups, 'rod')
        CHECK_TRUE(rod_group > 0, '&rod in the spec')
        if (rod_group == 0) return
        allocate(scene%rods(1))
        list = formulation_descriptors()
        claimed = '|'
        CHECK_TRUE(any(len_trim(list%own_rod_variables) > 0), 'some formulation owns variables')
        do k = 1, size(list)
            if (len_trim(list(k)%own_rod_variables) == 0) cycle
            variables = split_list(list(k)%own_rod_variables)
            do v = 1, size(variables)
                variable = trim(variables(v))
                what = variable // ' (' // trim(list(k)%name) // ')'
                CHECK_TRUE(find_variable(groups(rod_group), variable) > 0, what // ' is a &rod variable')
                given = rod_variable_given(scene%rods(1), variable, known)
                CHECK_TRUE(known, what // ' can be checked')
                CHECK_TRUE(.not. given, variable // ': not given on a default rod')
                CHECK_EQUAL(index(claimed, '|' // variable // '|'), 0, variable // ' claimed once')
                claimed = claimed // variable // '|'
            end do
        end do
        given = rod_variable_given(scene%rods(1), 'no_such_variable', known)
        CHECK_TRUE(.not. known, 'an unknown variable is reported as unknown')
        scene%rods(1)%em_variant = 'stander_stein'
        CHECK_TRUE(rod_variable_given(scene%rods(1), 'em_variant'), 'a given text is given')
    end subroutine test_own_rod_variables_known

    !> create_formulation builds each registered name and refuses others, listing the names.
    subroutine test_factory_through_descriptors()
        character(len=32), allocatable :: names(:)
        class(rod_formulation_t), allocatable :: rod
        type(error_t), allocatable :: err
        character(len=:), allocatable :: listing
        integer :: k
        names = formulation_names()
        do k = 1, size(names)
            call create_formulation(trim(names(k)), rod, err)
            CHECK_TRUE(.not. allocated(err), 'built: ' // trim(names(k)))
            CHECK_TRUE(allocated(rod), 'allocated: ' // trim(names(k)))
        end do
        call create_formulation('no_such_formulation', rod, err)
        CHECK_TRUE(allocated(err), 'an unknown name is an error')
        if (.not. allocated(err)) return
        listing = 'available: ' // available_formulations()
        CHECK_TRUE(index(err%describe(), listing) > 0, 'the error lists the names: ' // err%describe())
    end subroutine test_factory_through_descriptors

    !> Two rods form a shared system (solved by all ranks, its couplings in the system layer)
    !> exactly for a formulation whose descriptor couples through the system layer; one rod
    !> never does.
    subroutine test_bundle_where_described()
        type(formulation_descriptor_t), allocatable :: list(:)
        type(scene_t) :: scene
        integer :: k
        list = formulation_descriptors()
        CHECK_TRUE(any(list%system_couplings), 'some formulation couples through the system layer')
        allocate(scene%rods(2))
        do k = 1, size(list)
            scene%rods%formulation = list(k)%name
            CHECK_EQUAL(is_bundle(scene, [1, 2]), list(k)%system_couplings, 'two rods: ' // trim(list(k)%name))
            CHECK_TRUE(.not. is_bundle(scene, [1]), 'one rod: ' // trim(list(k)%name))
        end do
    end subroutine test_bundle_where_described

end module rs_test_formulations_registry

!> Test program: runs the tests of rs_test_formulations_registry; exits non-zero if any failed.
program test_registry
    use rs_test_formulations_registry, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_registry
