!> What the rest of rodsolve knows about one formulation (issue 22 item 4): its name, its row
!> of the capability matrix (DESIGN.md §1), the &rod variables only it reads, its roles in the
!> resolution of a scene, and the procedures that build it and describe it in the plan. Each
!> formulation folder has one descriptor module; rs_formulations_registry lists them, and the
!> factory, the input spec's allowed names, the capability checks, the plan and the generated
!> docs/user/capabilities.md all come from that list (docs/developer/adding_a_formulation.md).
module rs_formulations_descriptor
    use rs_core_error, only: error_t, error_list_t
    use rs_model_scene, only: scene_t, rod_input_t
    use rs_model_capabilities, only: capability_t
    use rs_formulations_formulation, only: rod_formulation_t
    implicit none
    private

    abstract interface
        !> Allocate the formulation object (its init follows).
        subroutine create_interface(formulation)
            import :: rod_formulation_t
            class(rod_formulation_t), allocatable, intent(out) :: formulation
        end subroutine create_interface

        !> The plan lines of rod `i` of `scene` ('!     ' lines, each ending in a new line); an
        !> error if the rod cannot be built.
        subroutine plan_lines_interface(scene, i, lines, err)
            import :: scene_t, error_t
            type(scene_t), intent(in) :: scene
            integer, intent(in) :: i
            character(len=:), allocatable, intent(out) :: lines
            type(error_t), allocatable, intent(out) :: err
        end subroutine plan_lines_interface

        !> Fill the defaults of the &rod variables that only this formulation reads.
        subroutine resolve_rod_interface(rod)
            import :: rod_input_t
            type(rod_input_t), intent(inout) :: rod
        end subroutine resolve_rod_interface

        !> Check values of &rod variables that this formulation reads in its own way; `here`
        !> is the message prefix (file, line, group and rod).
        subroutine check_rod_interface(rod, here, errors)
            import :: rod_input_t, error_list_t
            type(rod_input_t), intent(in) :: rod
            character(len=*), intent(in) :: here
            type(error_list_t), intent(inout) :: errors
        end subroutine check_rod_interface
    end interface

    !> One formulation, as its folder describes it.
    type, public :: formulation_descriptor_t
        !> The value of &rod formulation that selects it.
        character(len=32) :: name = ''
        !> Its row of the capability matrix (capability%formulation = name).
        type(capability_t) :: capability
        !> &rod variables ('|'-separated) that only this formulation reads: a value given on a
        !> rod of another formulation is refused (it would be silently ignored).
        character(len=128) :: own_rod_variables = ''
        !> The default of &run formulation_default, and what 'auto' chooses for 3D systems.
        logical :: default_choice = .false.
        !> What 'auto' chooses for systems that lie in one plane (if it can run them).
        logical :: auto_planar_choice = .false.
        !> Its rods are coupled by the system layer (src/system/: joints, plates and contact
        !> through node access, one object per rod), and a coupled system is solved by all ranks
        !> together (DESIGN.md §5); false: one object for the rods its joints join (shared
        !> unknowns, ph_planar).
        logical :: system_couplings = .false.
        !> Set for a semi-implicit formulation (one linear solve per step, no Newton): where its
        !> time step is described, for the plan.
        character(len=64) :: semi_implicit_step = ''
        procedure(create_interface), pointer, nopass :: create => null()
        procedure(plan_lines_interface), pointer, nopass :: plan_lines => null()
        !> Optional: defaults of its own &rod variables.
        procedure(resolve_rod_interface), pointer, nopass :: resolve_rod => null()
        !> Optional: checks of &rod values it reads in its own way.
        procedure(check_rod_interface), pointer, nopass :: check_rod => null()
    end type formulation_descriptor_t

end module rs_formulations_descriptor
