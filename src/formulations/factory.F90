#include "rs_macros.h"
!> Creates the formulation object a rod names (DESIGN.md §2, STYLE.md item 3), through the
!> descriptors of rs_formulations_registry: adding a formulation touches its folder and the
!> registry (docs/developer/adding_a_formulation.md), not this module.
module rs_formulations_factory
    use rs_core_error, only: error_t, set_error
    use rs_formulations_formulation, only: rod_formulation_t
    use rs_formulations_descriptor, only: formulation_descriptor_t
    use rs_formulations_registry, only: descriptor_of, available_formulations
    implicit none
    private

    public :: create_formulation, available_formulations

contains

    !> Allocate the formulation called `name`; an unknown or not yet available name is an
    !> error that lists the available ones.
    subroutine create_formulation(name, formulation, err)
        character(len=*), intent(in) :: name
        class(rod_formulation_t), allocatable, intent(out) :: formulation
        type(error_t), allocatable, intent(out) :: err
        type(formulation_descriptor_t) :: d
        character(len=:), allocatable :: message
        if (descriptor_of(trim(name), d)) then
            if (d%capability%available .and. associated(d%create)) then
                call d%create(formulation)
                return
            end if
        end if
        message = 'formulation ''' // trim(name) // &
            ''' is not available in this version; available: ' // available_formulations()
        RS_SET_ERROR(err, 'create_formulation', message)
    end subroutine create_formulation

end module rs_formulations_factory
