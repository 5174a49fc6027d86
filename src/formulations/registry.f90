!> The formulations of this build (issue 22 item 4): the one list of their descriptors
!> (rs_formulations_descriptor), one per formulation folder, and everything derived from it:
!> the names the input accepts, the capability rows that --check-input enforces and
!> docs/user/capabilities.md shows, the default and 'auto' choices, which coupled systems are
!> one shared bundle. The factory and the plan build and describe rods through it. This is the
!> only place outside the formulation folders that names formulations
!> (docs/developer/adding_a_formulation.md).
module rs_formulations_registry
    use rs_model_scene, only: scene_t
    use rs_model_capabilities, only: capability_t
    use rs_formulations_descriptor, only: formulation_descriptor_t
    use rs_ph_director_descriptor, only: ph_director_descriptor
    use rs_ph_planar_descriptor, only: ph_planar_descriptor, cl_em_planar_descriptor
    use rs_se3_pg_descriptor, only: se3_pg_descriptor
    use rs_se3_strand_descriptor, only: se3_strand_descriptor
    implicit none
    private

    public :: formulation_descriptors, descriptor_of, capability_of, registered_capabilities, &
        formulation_names, available_formulations, default_formulation, &
        auto_planar_formulation, is_bundle

contains

    !> Every formulation of this build, in the order of docs/user/capabilities.md.
    function formulation_descriptors() result(list)
        type(formulation_descriptor_t), allocatable :: list(:)
        list = [ph_director_descriptor(), ph_planar_descriptor(), cl_em_planar_descriptor(), &
            se3_pg_descriptor(), se3_strand_descriptor()]
    end function formulation_descriptors

    !> The descriptor called `name` in `d`; false (and `d` empty) if there is none.
    logical function descriptor_of(name, d) result(found)
        character(len=*), intent(in) :: name
        type(formulation_descriptor_t), intent(out) :: d
        type(formulation_descriptor_t), allocatable :: list(:)
        integer :: k
        list = formulation_descriptors()
        found = .false.
        do k = 1, size(list)
            if (trim(list(k)%name) /= trim(name)) cycle
            d = list(k)
            found = .true.
            return
        end do
    end function descriptor_of

    !> The capability row of formulation `name`: an unavailable row naming it if it is unknown.
    function capability_of(name) result(row)
        character(len=*), intent(in) :: name
        type(capability_t) :: row
        type(formulation_descriptor_t) :: d
        if (descriptor_of(name, d)) then
            row = d%capability
        else
            row%formulation = name
        end if
    end function capability_of

    !> The rows of the capability matrix, one per formulation.
    function registered_capabilities() result(rows)
        type(capability_t), allocatable :: rows(:)
        type(formulation_descriptor_t), allocatable :: list(:)
        integer :: k
        list = formulation_descriptors()
        allocate(rows(size(list)))
        do k = 1, size(list)
            rows(k) = list(k)%capability
        end do
    end function registered_capabilities

    !> The names of the formulations, in registry order.
    function formulation_names() result(names)
        character(len=32), allocatable :: names(:)
        type(formulation_descriptor_t), allocatable :: list(:)
        integer :: k
        list = formulation_descriptors()
        names = [(list(k)%name, k = 1, size(list))]
    end function formulation_names

    !> The names of the formulations this build can run, joined by `separator` (default ', ').
    function available_formulations(separator) result(text)
        character(len=*), intent(in), optional :: separator
        character(len=:), allocatable :: text, glue
        type(formulation_descriptor_t), allocatable :: list(:)
        integer :: k
        glue = ', '
        if (present(separator)) glue = separator
        list = formulation_descriptors()
        text = ''
        do k = 1, size(list)
            if (.not. list(k)%capability%available) cycle
            if (len(text) > 0) text = text // glue
            text = text // trim(list(k)%name)
        end do
    end function available_formulations

    !> The default of &run formulation_default, and what 'auto' chooses for a 3D system.
    function default_formulation() result(name)
        character(len=:), allocatable :: name
        name = first_name_with(default_choice=.true.)
    end function default_formulation

    !> What 'auto' chooses for a system of rods that lies in one plane.
    function auto_planar_formulation() result(name)
        character(len=:), allocatable :: name
        name = first_name_with(auto_planar_choice=.true.)
    end function auto_planar_formulation

    !> The rods `rods` (one coupled system of `scene`, rs_model_coupling) are solved as one
    !> shared bundle object (by all ranks together, DESIGN.md §5): they are coupled (several
    !> rods, plates or contact) and their formulation builds such bundles.
    logical function is_bundle(scene, rods)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:)
        type(formulation_descriptor_t) :: d
        is_bundle = size(rods) > 1 .or. scene%contact%given
        if (allocated(scene%plates)) is_bundle = is_bundle .or. size(scene%plates) > 0
        if (.not. is_bundle) return
        is_bundle = descriptor_of(trim(scene%rods(rods(1))%formulation), d)
        if (is_bundle) is_bundle = d%system_couplings
    end function is_bundle

    !> The first formulation with the role asked for.
    function first_name_with(default_choice, auto_planar_choice) result(name)
        logical, intent(in), optional :: default_choice, auto_planar_choice
        character(len=:), allocatable :: name
        type(formulation_descriptor_t), allocatable :: list(:)
        integer :: k
        list = formulation_descriptors()
        name = ''
        do k = 1, size(list)
            if (present(default_choice)) then
                if (.not. list(k)%default_choice) cycle
            end if
            if (present(auto_planar_choice)) then
                if (.not. list(k)%auto_planar_choice) cycle
            end if
            name = trim(list(k)%name)
            return
        end do
    end function first_name_with

end module rs_formulations_registry
