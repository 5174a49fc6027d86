#include "rs_macros.h"
!> Creates the formulation object a rod names (DESIGN.md §2, STYLE.md item 3). Adding a
!> formulation touches its folder and this list, nothing else.
module rs_formulations_factory
    use rs_core_error, only: error_t, set_error
    use rs_formulations_formulation, only: rod_formulation_t
    use rs_ph_director, only: ph_director_t
    use rs_ph_planar, only: ph_planar_t
    use rs_se3_pg, only: se3_pg_t
    use rs_se3_strand, only: se3_strand_t
    implicit none
    private

    public :: create_formulation

    !> Formulations this build can run.
    character(len=*), parameter, public :: available_formulations = &
        'ph_director, ph_planar, cl_em_planar, se3_pg, se3_strand'

contains

    !> Allocate the formulation called `name`; an unknown or not yet available name is an
    !> error that lists the available ones.
    subroutine create_formulation(name, formulation, err)
        character(len=*), intent(in) :: name
        class(rod_formulation_t), allocatable, intent(out) :: formulation
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: message
        select case (trim(name))
        case ('ph_director')
            allocate(ph_director_t :: formulation)
        case ('ph_planar', 'cl_em_planar')
            allocate(ph_planar_t :: formulation)
        case ('se3_pg')
            allocate(se3_pg_t :: formulation)
        case ('se3_strand')
            allocate(se3_strand_t :: formulation)
        case default
            message = 'formulation ''' // trim(name) // &
                ''' is not available in this version; available: ' // available_formulations
            RS_SET_ERROR(err, 'create_formulation', message)
        end select
    end subroutine create_formulation

end module rs_formulations_factory
