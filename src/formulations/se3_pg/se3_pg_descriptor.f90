!> se3_pg (seed 002) as the rest of rodsolve sees it (rs_formulations_descriptor).
module rs_se3_pg_descriptor
    use rs_core_error, only: error_t
    use rs_model_scene, only: scene_t
    use rs_model_capabilities, only: capability_t
    use rs_formulations_formulation, only: rod_formulation_t
    use rs_formulations_descriptor, only: formulation_descriptor_t
    use rs_se3_pg, only: se3_pg_t
    use rs_se3_pg_plan, only: se3_pg_plan_lines
    implicit none
    private

    public :: se3_pg_descriptor

contains

    !> The descriptor of formulation 'se3_pg'.
    function se3_pg_descriptor() result(d)
        type(formulation_descriptor_t) :: d
        d%name = 'se3_pg'
        ! seed 002 (methods/se3_petrov_galerkin.md §3.4, §7, §10): clamped, pinned, driven,
        ! sliding (along a coordinate axis) and held ends (issue 26 item 3) by elimination,
        ! also the twist alone (one component of the end's rotation vector, issue 27 item 2),
        ! dead and follower end loads, dead distributed loads and gravity,
        ! statics (&time quasistatic) and dynamics by the midpoint rule or the paper's
        ! generalized-alpha scheme (§7.3); any reference the SE(3) interpolation represents;
        ! Kelvin-Voigt viscosity and drag in both schemes (docs/theory/se3_pg.md, "Damping").
        ! Prestretched starts (issue 26 item 3, docs/theory/prestretched_starts.md): axial
        ! prestrain, the initial equilibrium (its statics continued in a dynamic run) and
        ! supports released at a time (held rows).
        d%capability = capability_t(formulation=d%name, available=.true., &
            end_kinds='clamped|pinned|free|driven|sliding|held', held_twist=.true., &
            load_places='start|end|distributed|gravity', load_frames='spatial|follower', &
            constraints='none', quasistatic=.true., viscoelastic=.false., actuation=.false., &
            curved_reference=.true., joints='rigid|spherical|revolute', end_plates=.true., &
            contact=.true., planar=.false., drive='pose', order_4=.true., &
            adaptive=.true., generalized_alpha=.true., damping=.true., &
            segments=.true., prestrain=.true., initial_equilibrium=.true., release=.true., &
            modes=.true., damped_modes=.false., buckling=.true.)
        ! Arc-length continuation of its statics (docs/theory/continuation.md).
        d%capability%continuation = .true.
        ! Joints, end plates and rod-rod contact through the system layer (src/system/) on
        ! se3_pg's node access (se3_pg%nodes, its tie rows in rs_se3_pg_tie): issue 22 item 5.
        d%system_couplings = .true.
        d%create => create
        d%plan_lines => plan_lines
    end function se3_pg_descriptor

    !> One rod (its couplings are the system layer's).
    subroutine create(formulation)
        class(rod_formulation_t), allocatable, intent(out) :: formulation
        allocate(se3_pg_t :: formulation)
    end subroutine create

    !> Its plan never fails (it reads scene data only): `err` stays unallocated.
    subroutine plan_lines(scene, i, lines, err)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i
        character(len=:), allocatable, intent(out) :: lines
        type(error_t), allocatable, intent(out) :: err
        lines = se3_pg_plan_lines(scene, i)
    end subroutine plan_lines

end module rs_se3_pg_descriptor
