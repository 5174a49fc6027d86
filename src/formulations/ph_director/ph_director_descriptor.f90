!> ph_director as the rest of rodsolve sees it (rs_formulations_descriptor): its capability row,
!> its role as the default (and 3D 'auto') formulation, its rods coupled by the system layer, its plan.
module rs_ph_director_descriptor
    use rs_formulations_formulation, only: rod_formulation_t
    use rs_formulations_descriptor, only: formulation_descriptor_t
    use rs_model_capabilities, only: capability_t
    use rs_ph_director, only: ph_director_t
    use rs_ph_director_plan, only: ph_director_plan_lines
    implicit none
    private

    public :: ph_director_descriptor

contains

    !> The descriptor of formulation 'ph_director'.
    function ph_director_descriptor() result(d)
        type(formulation_descriptor_t) :: d
        d%name = 'ph_director'
        ! seed 000 §2.9 and §6.1: clamped (Dirichlet) and free (Neumann) ends; dead end
        ! loads, distributed loads and gravity. The extensions of seed 000 §5
        ! (methods/ph_director_3d.md §2.3, §3, §6.3): shear-rigid and inextensible
        ! constraints, quasistatics, Maxwell branches, actuators; and a curved stress-free
        ! reference (the reference strains at the Gauss points, docs/theory/ph_director.md).
        ! Bundles (issue 10, DESIGN.md §5): rigid, spherical and revolute joints and end
        ! plates as constraints with multipliers on the end nodes (rs_ph_director_tie), and
        ! rod-rod and self contact by an energy-consistent penalty (rs_contact_potential).
        ! Damping (issue 26 item 1, docs/theory/ph_director.md "Damping"): Kelvin-Voigt as a
        ! Maxwell branch of zero compliance (seed 000 Remark 5.2), condensed per element, and
        ! the external drags, all in the exact energy balance.
        ! Supports and loads (issue 26 item 2): pinned ends (phi held, directors free; the
        ! Dirichlet part of methods §2.9 on phi alone); follower end and distributed loads
        ! (rs_ph_director_follower: evaluated at the midpoint directors, their work booked at
        ! that value, so the balance stays exact); driven ends (the pose prescribed, the
        ! drive's work booked from the reaction, so the balance stays exact), sliding ends and
        ! ends held in chosen directions (issue 26 item 3; held coordinates eliminated).
        ! Prestrain (issue 26 item 3, docs/theory/prestretched_starts.md): the reference
        ! strains Gamma_0 / (1 + prestrain) with the consistent initial stresses.
        ! Modes (issue 27 item 1) from the first-order pencil of the midpoint step; linearized
        ! buckling (item 2) from the tangent of the quasistatic endpoint equilibrium (traits
        ! static_tangent, docs/theory/modes.md).
        d%capability = capability_t(formulation=d%name, available=.true., &
            end_kinds='clamped|pinned|free|driven|sliding|held|body', &
            load_places='start|end|distributed|gravity', drive='pose', &
            load_frames='spatial|follower', constraints='none|kirchhoff|inextensible|rigid', quasistatic=.true., &
            viscoelastic=.true., actuation=.true., curved_reference=.true., prestressed=.true., &
            joints='rigid|spherical|revolute', end_plates=.true., floating_plates=.true., &
            contact=.true., order_4=.true., adaptive=.true., damping=.true., &
            segments=.true., prestrain=.true., initial_equilibrium=.true., modes=.true., &
            damped_modes=.true., buckling=.true.)
        ! Arc-length continuation of its endpoint statics (docs/theory/continuation.md).
        d%capability%continuation = .true.
        d%default_choice = .true.
        d%system_couplings = .true.
        d%create => create
        d%plan_lines => ph_director_plan_lines
    end function ph_director_descriptor

    subroutine create(formulation)
        class(rod_formulation_t), allocatable, intent(out) :: formulation
        allocate(ph_director_t :: formulation)
    end subroutine create

end module rs_ph_director_descriptor
