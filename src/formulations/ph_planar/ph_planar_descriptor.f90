!> ph_planar and cl_em_planar (seed 001) as the rest of rodsolve sees them
!> (rs_formulations_descriptor): one formulation object (rs_ph_planar, which reads the element
!> variant from the rod's formulation name), two names with one capability row.
module rs_ph_planar_descriptor
    use rs_core_error, only: error_t, error_list_t
    use rs_core_strings, only: str
    use rs_model_scene, only: scene_t, rod_input_t, unset_int
    use rs_model_capabilities, only: capability_t
    use rs_formulations_formulation, only: rod_formulation_t
    use rs_formulations_descriptor, only: formulation_descriptor_t
    use rs_ph_planar, only: ph_planar_t
    use rs_ph_planar_plan, only: ph_planar_plan_lines
    implicit none
    private

    public :: ph_planar_descriptor, cl_em_planar_descriptor

contains

    !> The descriptor of formulation 'ph_planar' (PH-EM, methods/ph_planar.md).
    function ph_planar_descriptor() result(d)
        type(formulation_descriptor_t) :: d
        d = planar_descriptor('ph_planar')
        d%auto_planar_choice = .true.
    end function ph_planar_descriptor

    !> The descriptor of formulation 'cl_em_planar' (the Stander–Stein comparison scheme,
    !> seed 001 §5): its own em_variant, and reduced quadrature by default.
    function cl_em_planar_descriptor() result(d)
        type(formulation_descriptor_t) :: d
        d = planar_descriptor('cl_em_planar')
        d%own_rod_variables = 'em_variant'
        d%resolve_rod => resolve_cl_em_rod
    end function cl_em_planar_descriptor

    !> What both planar names share.
    function planar_descriptor(name) result(d)
        character(len=*), intent(in) :: name
        type(formulation_descriptor_t) :: d
        d%name = name
        ! seed 001 (methods/ph_planar.md §2.5, §5, §6.3): straight planar rods with
        ! clamped, pinned (ground pin: position fixed, angle free), sliding (along a
        ! planar coordinate axis; issue 26 item 3), held (the planar coordinates its held
        ! directions fix) and free ends; dead end
        ! loads, distributed loads and gravity in the plane; quasistatics (§4.7); revolute
        ! joints as shared nodal positions (§6.3) and rigid joints as shared positions and
        ! angles. Kelvin-Voigt viscosity and drag (issue 26, docs/theory/ph_planar.md
        ! "Damping") with their dissipation in the exact energy balance of every scheme.
        ! Prestretched starts (issue 26 item 3, docs/theory/prestretched_starts.md): axial
        ! prestrain, the initial equilibrium (the equilibrium rows of quasistatics in a
        ! dynamic run) and supports released at a time (held rows).
        ! Modes and linearized buckling (&modes, docs/theory/modes.md) from the step
        ! Jacobian at rest, 2 M / h^2 + K / 2 with every scheme (cl-EM's Z1, Z2 are 1 there).
        d%capability = capability_t(formulation=name, available=.true., &
            end_kinds='clamped|pinned|free|sliding|held', &
            load_places='start|end|distributed|gravity', &
            load_frames='spatial', constraints='none', quasistatic=.true., &
            viscoelastic=.false., actuation=.false., curved_reference=.false., &
            joints='revolute|rigid', planar=.true., order_4=.true., adaptive=.true., &
            damping=.true., segments=.true., prestrain=.true., initial_equilibrium=.true., &
            release=.true., modes=.true., damped_modes=.false., buckling=.true.)
        ! Arc-length continuation (docs/theory/continuation.md) on the static rows of either
        ! scheme (cl_em_planar's residual has a rounding floor: newton_atol about 3e-7 of the
        ! loads).
        d%capability%continuation = .true.
        d%create => create
        d%plan_lines => plan_lines
        d%check_rod => check_planar_rod
    end function planar_descriptor

    !> One object for both names; a jointed planar system is one object already (its joints
    !> share nodal unknowns, methods/ph_planar.md §6.3; descriptor system_couplings false).
    subroutine create(formulation)
        class(rod_formulation_t), allocatable, intent(out) :: formulation
        allocate(ph_planar_t :: formulation)
    end subroutine create

    !> Its plan never fails (it reads scene data only): `err` stays unallocated.
    subroutine plan_lines(scene, i, lines, err)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i
        character(len=:), allocatable, intent(out) :: lines
        type(error_t), allocatable, intent(out) :: err
        call ph_planar_plan_lines(scene, i, lines)
    end subroutine plan_lines

    !> em_variant defaults to 'stander_stein'; the full (2-point) quadrature of the axial and
    !> shear terms locks in bending (methods/ph_planar.md §5.1-5.2, the roll-up): cl_em_planar's
    !> default is the reduced one (issue 21 item 16).
    subroutine resolve_cl_em_rod(rod)
        type(rod_input_t), intent(inout) :: rod
        if (len_trim(rod%em_variant) == 0) rod%em_variant = 'stander_stein'
        if (rod%n_gauss == unset_int) rod%n_gauss = 1
    end subroutine resolve_cl_em_rod

    !> The planar elements take n_gauss 1 or 2 (for cl_em_planar the quadrature of the axial
    !> and shear terms, 1 reduced, 2 full: methods/ph_planar.md §5.1).
    subroutine check_planar_rod(rod, here, errors)
        type(rod_input_t), intent(in) :: rod
        character(len=*), intent(in) :: here
        type(error_list_t), intent(inout) :: errors
        if (rod%n_gauss > 2) call errors%add(here // 'n_gauss: ' // &
            str(rod%n_gauss) // ' given, but the planar elements take 1 or 2 Gauss points ' // &
            '(cl_em_planar: for its axial and shear terms, 1 = reduced, 2 = full); allowed: 1, 2')
    end subroutine check_planar_rod

end module rs_ph_planar_descriptor
