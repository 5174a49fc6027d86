!> se3_strand (seed 004) as the rest of rodsolve sees it (rs_formulations_descriptor): its
!> capability row, its own &rod variables (damping and free_end), its semi-implicit step.
module rs_se3_strand_descriptor
    use rs_core_error, only: error_t
    use rs_model_scene, only: scene_t, rod_input_t
    use rs_model_capabilities, only: capability_t
    use rs_formulations_formulation, only: rod_formulation_t
    use rs_formulations_descriptor, only: formulation_descriptor_t
    use rs_se3_strand, only: se3_strand_t
    use rs_se3_strand_plan, only: se3_strand_plan_lines
    implicit none
    private

    public :: se3_strand_descriptor

contains

    !> The descriptor of formulation 'se3_strand'.
    function se3_strand_descriptor() result(d)
        type(formulation_descriptor_t) :: d
        d%name = 'se3_strand'
        ! seed 004 (methods/se3_strands.md §2.5, §2.7, §3.4, §3.7): motion prescribed at
        ! s = 0 (a clamp, or a driven end whose velocity is prescribed, P0 = M V0(t)) or a
        ! free start (issue 26 item 4, docs/theory/se3_strand.md "A free start") and
        ! stress at s = L (free, with its end load); drag, gravity and follower tip loads;
        ! any relaxed (curved) reference shape; statics by damped dynamics instead of
        ! quasistatics. Its damping: seed 004's external and internal laws (&rod
        ! external_damping, internal_damping, its own) and the Kelvin-Voigt stress and drag of
        ! every damped formulation (kelvin_voigt_time, drag, angular_drag), not Maxwell
        ! branches. &segment: a stiffness per segment, an inertia per node (issue 26 item 5).
        ! Modes about the reference, damped ones included (first-order pencil of its one-step
        ! scheme with dF/dX_n, docs/theory/modes.md), not with dead loads.
        d%capability = capability_t(formulation=d%name, available=.true., &
            end_kinds='clamped|driven|free', end_kinds_at_end='free', &
            end_kinds_note='; se3_strand prescribes the motion or no stress at s = 0 and the ' // &
            'stress at s = L (methods/se3_strands.md §3.4; docs/theory/se3_strand.md)', &
            load_places='end|distributed|gravity', load_frames='spatial|follower', &
            constraints='none', quasistatic=.false., viscoelastic=.false., actuation=.false., &
            curved_reference=.true., prestressed=.true., joints='', planar=.false., &
            relaxation=.true., damping=.true., drive='velocity', segments=.true., &
            prestrain=.true., modes=.true., damped_modes=.true.)
        ! The damping of seed 004 (methods/se3_strands.md §2.7) and the treatment of the free
        ! end are read by this formulation only.
        d%own_rod_variables = 'free_end|external_damping|internal_damping'
        d%semi_implicit_step = 'methods/se3_strands.md §3.5'
        d%create => create
        d%plan_lines => plan_lines
        d%resolve_rod => resolve_rod
    end function se3_strand_descriptor

    !> One rod (se3_strand has no couplings).
    subroutine create(formulation)
        class(rod_formulation_t), allocatable, intent(out) :: formulation
        allocate(se3_strand_t :: formulation)
    end subroutine create

    !> Its plan never fails (it reads scene data only): `err` stays unallocated.
    subroutine plan_lines(scene, i, lines, err)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i
        character(len=:), allocatable, intent(out) :: lines
        type(error_t), allocatable, intent(out) :: err
        lines = se3_strand_plan_lines(scene, i)
    end subroutine plan_lines

    !> free_end defaults to 'balanced'.
    subroutine resolve_rod(rod)
        type(rod_input_t), intent(inout) :: rod
        if (len_trim(rod%free_end) == 0) rod%free_end = 'balanced'
    end subroutine resolve_rod

end module rs_se3_strand_descriptor
