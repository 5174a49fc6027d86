!> Resolution and checks of a scene that was read without errors (DESIGN.md §6), in three
!> concerns, each a module of its own: values of one group and the defaults derived from them
!> (rs_io_input_values), checks across groups (rs_io_input_cross_check), and the scene against
!> what its formulations can do (rs_io_input_capability_check, from the formulations'
!> descriptors). resolve_scene runs the first two and the resolution of formulations; the
!> capability check runs after it (rs_io_input_file, rs_io_sweep). Every problem is added to
!> `errors`, naming the file, line, group and variable.
module rs_io_input_check
    use rs_core_error, only: error_list_t
    use rs_core_strings, only: str
    use rs_model_scene, only: scene_t, unset_real
    use rs_io_input_check_common, only: at
    use rs_formulations_registry, only: default_formulation
    use rs_io_input_values, only: check_step_count, check_relaxation, check_output_and_restart, &
        resolve_rod, default_output_path, resolve_segments
    use rs_io_input_cross_check, only: check_unique_names, check_bcs, check_loads, &
        check_actuators, check_joints, resolve_joint_axes, resolve_plates, resolve_contact, &
        resolve_obstacles
    use rs_io_input_capability_check, only: resolve_auto_formulations, &
        resolve_formulation_options, check_joint_formulations, check_capabilities, &
        check_rod_capabilities
    implicit none
    private

    public :: resolve_scene, default_output_path, check_capabilities, check_rod_capabilities

contains

    !> Fill derived defaults of `scene` and cross-check it; problems go to `errors`.
    subroutine resolve_scene(scene, errors)
        type(scene_t), intent(inout) :: scene
        type(error_list_t), intent(inout) :: errors
        logical, allocatable :: geometry_ok(:)
        integer :: i

        if (len_trim(scene%output%path) == 0) scene%output%path = default_output_path(scene%source_file)
        if (len_trim(scene%run%formulation_default) == 0) &
            scene%run%formulation_default = default_formulation()
        if (scene%time%dt /= unset_real .and. scene%time%t_end /= unset_real) then
            if (scene%time%dt > scene%time%t_end) call errors%add(at(scene, 0) // '&time dt: ' // &
                str(scene%time%dt) // ' is larger than t_end = ' // str(scene%time%t_end))
            call check_step_count(scene, errors)
        end if
        call check_relaxation(scene, errors)
        call check_output_and_restart(scene, errors)
        if (size(scene%rods) == 0) call errors%add(scene%source_file // ': the scene has no &rod group')
        allocate(geometry_ok(size(scene%rods)))
        do i = 1, size(scene%rods)
            call resolve_rod(scene, i, geometry_ok(i), errors)
        end do
        call resolve_segments(scene, geometry_ok, errors)
        if (.not. allocated(scene%joints)) allocate(scene%joints(0))
        if (.not. allocated(scene%plates)) allocate(scene%plates(0))
        call check_unique_names(scene, errors)
        call check_bcs(scene, geometry_ok, errors)
        call check_loads(scene, errors)
        call check_actuators(scene, errors)
        call check_joints(scene, geometry_ok, errors)
        call resolve_joint_axes(scene)
        call resolve_plates(scene, geometry_ok, errors)
        call resolve_contact(scene, geometry_ok, errors)
        call resolve_obstacles(scene, errors)
        ! 'auto' needs every rod, load and joint resolved: it looks at whole systems.
        call resolve_auto_formulations(scene)
        call resolve_formulation_options(scene)
        call check_joint_formulations(scene, errors)
    end subroutine resolve_scene

end module rs_io_input_check
