#include "rs_macros.h"
!> Creates the formulation object a rod names (DESIGN.md §2, STYLE.md item 3). Adding a
!> formulation touches its folder and this list, nothing else.
module rs_formulations_factory
    use rs_core_error, only: error_t, set_error
    use rs_formulations_formulation, only: rod_formulation_t
    use rs_ph_director, only: ph_director_t
    use rs_ph_bundle, only: ph_bundle_t
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
    subroutine create_formulation(name, formulation, err, bundle)
        character(len=*), intent(in) :: name
        class(rod_formulation_t), allocatable, intent(out) :: formulation
        type(error_t), allocatable, intent(out) :: err
        !> The system couples rods (joints, plates, contact): the bundle of the formulation
        !> (ph_director only; issue 10). Default false.
        logical, intent(in), optional :: bundle
        character(len=:), allocatable :: message
        logical :: coupled
        coupled = .false.
        if (present(bundle)) coupled = bundle
        select case (trim(name))
        case ('ph_director')
            if (coupled) then
                allocate(ph_bundle_t :: formulation)
            else
                allocate(ph_director_t :: formulation)
            end if
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
