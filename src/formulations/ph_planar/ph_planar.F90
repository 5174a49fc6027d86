#include "rs_macros.h"
!> The planar rods of seed 001 (methods/ph_planar.md): one object per *system*, a rod or the rods
!> that revolute and rigid joints couple (the four-bar of §6.3), solved as one midpoint step
!> problem. Three schemes share the nodal unknowns (x, y, theta) and this assembly:
!>
!> - `ph_planar` (PH-EM, methods §4.1-4.3): the implicit midpoint rule on the port-Hamiltonian
!>   system, element strains (Gamma1, Gamma2, kappa) as unknowns (P0), or eliminated per element
!>   (`&solver condense_stresses`, exact: C1, C2 are diagonal, methods §3.5);
!> - `cl_em_planar` (methods §5.1): Stander and Stein's displacement-based energy-momentum scheme
!>   with the correction factors Z1, Z2 (`n_gauss` 1 = reduced, 2 = full integration);
!> - `cl_em_planar` with `em_variant = 'ph_irreducible'` (PH-EMi, methods §5.2): the rate-form
!>   strain update kept as Gauss-point history.
!>
!> Joints share nodal unknowns (methods §6.3, the authors' master-slave elimination; DESIGN.md
!> §5): a revolute joint shares the position of the two rod ends, a rigid joint also the angle.
!> Supports fix unknowns (clamped: x, y, theta; pinned: x, y); a support released at a time
!> (&bc release_time) keeps them as unknowns with held rows until then (rs_formulations_
!> held_rows, docs/theory/prestretched_starts.md). Loads are inputs evaluated at
!> t_{n+1/2} (methods §3.4, §4.1), so the energy balance H_{n+1} - H_n = f(t_{n+1/2}) . (q_{n+1}
!> - q_n) is exact whatever the load; gravity is a distributed input (methods §6.3).
!>
!> The state X = (q, v, history): nodal unknowns q, their velocities v (the midpoint rule
!> recovers v_{n+1} = 2 (q_{n+1} - q_n) / h - v_n, methods §4.3), and per element the mixed
!> strains (PH-EM) or the Gauss-point strains (PH-EMi). The step unknowns Y are the free entries
!> of q_{n+1}, followed by the element strains of PH-EM when they are not condensed.
!>
!> The plane (rs_model_planarity) maps the scene's 3D input to planar coordinates and the
!> results back: positions, directors rotated about the plane normal, 3D momenta.
module rs_ph_planar
    use rs_core_kinds, only: rk, pi
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: str, vector_text
    use rs_model_scene, only: scene_t, rod_input_t, load_applies_to, unset_real, &
        element_properties, axial_reference
    use rs_model_damping, only: kv_axial, kv_shear1, kv_shear2, kv_bend1, kv_bend2
    use rs_model_rod_history, only: rod_history_t
    use rs_model_time_function, only: time_function_t, time_function_from_load
    use rs_model_planarity, only: plane_t, plane_of_rods, point_in_plane, vector_in_plane, &
        point_from_plane, vector_from_plane, angle_in_plane, cross, planar_coordinate_axis, &
        planar_held
    use rs_model_support, only: end_hold, hold_list, twist_hold_refusal
    use rs_assembly_csr_pattern, only: csr_builder_t, csr_pattern_t
    use rs_formulations_formulation, only: rod_formulation_t, formulation_traits_t, &
        state_measures_t, state_valid, state_invalid, modal_second_order
    use rs_formulations_energy_sentinel, only: step_energy_t, energy_consistent, energy_unchecked
    use rs_formulations_held_rows, only: held_rows_t
    use rs_ph_planar_element, only: ph_em_residual, ph_em_jacobian, ph_em_condensed, &
        cl_em_residual, cl_em_jacobian, ph_emi_residual, ph_emi_jacobian, ph_emi_strains, &
        element_mass, mixed_strain_energy, compatible_strain_energy, compatible_strains, &
        ph_emi_strain_energy, ph_em_static, ph_em_static_condensed, ph_em_projected_strains, &
        cl_em_static, viscous_dissipation, reference_stretches
    implicit none
    private

    !> The schemes (methods §5.3).
    integer, parameter :: scheme_ph_em = 1, scheme_stander_stein = 2, scheme_ph_irreducible = 3

    !> A load on one rod: at a node (node > 0) or distributed per length (node = 0).
    type :: planar_load_t
        integer :: rod = 0
        integer :: node = 0
        !> Gravity: `force` is the acceleration, times each element's mass per length.
        logical :: gravity = .false.
        real(rk) :: force(2) = 0.0_rk
        real(rk) :: moment = 0.0_rk
        type(time_function_t) :: factor
    end type planar_load_t

    !> One rod of the system: mesh, section, and where its nodes' unknowns are.
    type :: planar_rod_t
        character(len=:), allocatable :: name
        integer :: n_elements = 0
        real(rk) :: length = 0.0_rk
        !> (EA, GA, EI) in the plane: bending about the plane normal (methods §2.4).
        real(rk) :: stiffness(3) = 0.0_rk
        !> Damping (docs/theory/damping.md, docs/theory/ph_planar.md "Damping"): the Kelvin-Voigt
        !> viscosities tau_i k_i of (EA, GA, EI), the drag per length against the centreline
        !> velocity (x', y') and the angular drag against theta'; `viscous` and `dragged` say
        !> whether any is non-zero (an undamped rod skips the terms).
        real(rk) :: viscosity(3) = 0.0_rk
        real(rk) :: drag = 0.0_rk, angular_drag = 0.0_rk
        logical :: viscous = .false., dragged = .false.
        real(rk) :: rho_a = 0.0_rk, rho_i = 0.0_rk
        !> Per element of the rod (&segment, issue 26 item 5): (EA, GA, EI), their viscosities,
        !> (rhoA, rhoI) (zero in a quasistatic run) and the mass per length as given (its weight).
        real(rk), allocatable :: element_stiffness(:, :), element_viscosity(:, :), &
            element_rho(:, :), element_line_mass(:)
        !> Reference angle theta_0 of the straight rod (methods §3.1).
        real(rk) :: theta0 = 0.0_rk
        !> The reference axial strain per unit given length, 1 / (1 + prestrain) (&rod
        !> prestrain; docs/theory/prestretched_starts.md); 1 for a stress-free start.
        real(rk) :: axial_reference = 1.0_rk
        !> Initial 3D directors (columns d1, d2, d3) and the maps of the planar stress (N1, N2,
        !> M) to the material 3D components (N1, N2, N3, M1, M2, M3).
        real(rk) :: directors0(3, 3) = 0.0_rk
        real(rk) :: stress_map(6, 3) = 0.0_rk
        !> dofs(:, k): indices into q of x, y, theta of node k.
        integer, allocatable :: dofs(:, :)
        !> First element of the rod in the system's element numbering.
        integer :: first_element = 0
    end type planar_rod_t

    !> A system of planar rods (one rod, or rods joined together).
    type, extends(rod_formulation_t), public :: ph_planar_t
        character(len=:), allocatable :: formulation_name
        integer :: scheme = scheme_ph_em
        logical :: condensed = .false.
        logical :: quasistatic = .false.
        integer :: n_gauss = 2
        type(plane_t) :: plane
        type(planar_rod_t), allocatable :: rods(:)
        type(planar_load_t), allocatable :: loads(:)
        !> Sizes: nodal unknowns q, elements, history values per element, step unknowns.
        integer :: n_q = 0, n_elements = 0, n_history = 0, n_free = 0, n_y = 0
        !> unknown_of(i): index of q(i) in Y (0: fixed by a support).
        integer, allocatable :: unknown_of(:)
        !> Supports released at a time (&bc release_time): their q indices and times (set by
        !> fix_supports), and the held rows of their unknowns (set with the pattern).
        integer, allocatable :: released_q(:)
        real(rk), allocatable :: released_time(:)
        type(held_rows_t) :: held
        !> Per element: its rod, its index there, its 6 q indices.
        integer, allocatable :: element_rod(:), element_dofs(:, :)
        real(rk), allocatable :: element_length(:)
        !> Per element in system order: (EA, GA, EI) and their Kelvin-Voigt viscosities (the
        !> rods' element_stiffness, element_viscosity).
        real(rk), allocatable :: stiffness(:, :), viscosity(:, :)
        !> Per element, reference(:, g, e): the stretch Lambda^T d_s r of its stress-free state
        !> at Gauss point g, from which the strains formed from positions are measured
        !> (planar_element reference_stretches of the initial state, set_initial_state).
        real(rk), allocatable :: reference(:, :, :)
        !> Per element: the consistent mass (6, 6) in its q ordering (methods §3.2), built once:
        !> residual and Jacobian need it at every Newton iteration.
        real(rk), allocatable :: mass(:, :, :)
        !> Per element of a dragged rod: the consistent drag matrix (6, 6), element_mass with
        !> (drag, angular_drag) for (rhoA, rhoI); zero elsewhere. Allocated only when a rod of
        !> the system has drag.
        real(rk), allocatable :: drag_matrix(:, :, :)
        !> Jacobian pattern and, per element, the CSR position of entry (i, j) of its local
        !> matrix over (q_a, q_b, strains) (0: a fixed row or column).
        type(csr_pattern_t) :: pattern
        integer, allocatable :: element_map(:, :, :)
        !> The initial state X (set at init from the scene).
        real(rk), allocatable :: initial(:)
        ! Workspace, sized at init (no allocation in the time loop).
        real(rk), allocatable :: q_1(:), f_ext(:), f_rod(:, :)
        !> The nodal angles (their q indices, each once) and whether `update` keeps them near
        !> zero: theta is not wrapped by the scheme, and the round-off of the inertia rows grows
        !> as eps |theta| / h^2, so a spinning rod's Newton residual could not reach newton_atol
        !> after a few turns (docs/stability.md). A shift of every angle by the same 2 pi k changes
        !> nothing physical; only systems with no angle fixed by a support are shifted.
        integer, allocatable :: theta_dofs(:)
        logical :: wrap_theta = .false.
        !> The shift 2 pi k that the last `update` subtracted (added back in the loads' work).
        real(rk) :: theta_shift = 0.0_rk
        !> The next steps solve the equilibrium at load time t_static (a quasistatic run's
        !> endpoint or initial equilibrium, DESIGN.md §3): as a continuation (set_step_problem
        !> with continue_from), a step to the pseudo-time tau solves R(Y) = (1 - tau) anchor,
        !> its strain rows scaled as a step of length row_scale (always 1: the pseudo-time
        !> runs over [0, 1]).
        logical :: static = .false., continuing = .false.
        real(rk) :: t_static = 0.0_rk, row_scale = 0.0_rk
        real(rk), allocatable :: anchor(:)
    contains
        procedure :: init => planar_init
        procedure :: n_state => planar_n_state
        procedure :: error_entries => planar_error_entries
        procedure :: n_unknown => planar_n_unknown
        procedure :: jacobian_pattern => planar_jacobian_pattern
        procedure :: initial_state => planar_initial_state
        procedure :: predictor => planar_predictor
        procedure :: update => planar_update
        procedure :: step_residual => planar_step_residual
        procedure :: step_jacobian => planar_step_jacobian
        procedure :: accept_step => planar_accept_step
        procedure :: init_history => planar_init_history
        procedure :: record => planar_record
        procedure :: describe => planar_describe
        procedure :: traits => planar_traits
        procedure :: set_step_problem => planar_set_step_problem
        procedure :: state_measures => planar_state_measures
        procedure :: path_weights => planar_path_weights
        !> Kinetic and strain energy of one rod in state x.
        procedure :: rod_energy
        !> The energy one rod's damping dissipated over a step.
        procedure :: rod_dissipation
        procedure, private :: full_q, element_strains, load_vectors
    end type ph_planar_t

contains

    ! ---- Building the system ----------------------------------------------------------------

    subroutine planar_init(this, scene, rods, err)
        class(ph_planar_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:)
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: message
        integer :: r, e, next

        this%formulation_name = trim(scene%rods(rods(1))%formulation)
        this%quasistatic = scene%time%quasistatic
        this%n_gauss = scene%rods(rods(1))%n_gauss
        select case (this%formulation_name)
        case ('ph_planar')
            this%scheme = scheme_ph_em
            this%condensed = scene%solver%condense_stresses
        case ('cl_em_planar')
            this%scheme = scheme_stander_stein
            if (trim(scene%rods(rods(1))%em_variant) == 'ph_irreducible') &
                this%scheme = scheme_ph_irreducible
        end select
        if (this%n_gauss < 1 .or. this%n_gauss > 2) then
            message = 'rod ''' // trim(scene%rods(rods(1))%name) // ''': the planar elements ' // &
                'take n_gauss = 1 or 2, not ' // str(this%n_gauss)
            RS_SET_ERROR(err, 'ph_planar%init', message)
            return
        end if
        this%plane = plane_of_rods(scene, rods)
        if (.not. this%plane%found) then
            message = 'rod ''' // trim(scene%rods(rods(1))%name) // ''' is not planar: ' // &
                this%plane%reason
            RS_SET_ERROR(err, 'ph_planar%init', message)
            return
        end if

        allocate(this%rods(size(rods)))
        next = 0
        do r = 1, size(rods)
            call build_rod(this, scene%rods(rods(r)), element_properties(scene, &
                scene%rods(rods(r)), scene%rods(rods(r))%n_elements), this%rods(r))
            this%rods(r)%first_element = next + 1
            next = next + this%rods(r)%n_elements
        end do
        this%n_elements = next
        call number_dofs(this, scene, rods)
        call fix_supports(this, scene, rods, err)
        RS_RETURN_IF_ERROR(err)
        call read_loads(this, scene, rods, err)
        RS_RETURN_IF_ERROR(err)

        ! Elements in system order.
        allocate(this%element_rod(this%n_elements), this%element_dofs(6, this%n_elements), &
            this%element_length(this%n_elements), this%mass(6, 6, this%n_elements), &
            this%stiffness(3, this%n_elements), this%viscosity(3, this%n_elements))
        do r = 1, size(this%rods)
            associate (rod => this%rods(r))
                do e = 1, rod%n_elements
                    next = rod%first_element + e - 1
                    this%element_rod(next) = r
                    this%element_dofs(:, next) = [rod%dofs(:, e), rod%dofs(:, e + 1)]
                    this%element_length(next) = rod%length / real(rod%n_elements, rk)
                    this%stiffness(:, next) = rod%element_stiffness(:, e)
                    this%viscosity(:, next) = rod%element_viscosity(:, e)
                    call element_mass(this%element_length(next), rod%element_rho(1, e), &
                        rod%element_rho(2, e), this%mass(:, :, next))
                end do
            end associate
        end do
        ! The drag force -C v_mid of the step (docs/theory/ph_planar.md "Damping"): C the
        ! consistent matrix of int (drag |v|^2 + angular_drag theta'^2) ds over P1 velocities.
        if (any(this%rods%dragged)) then
            allocate(this%drag_matrix(6, 6, this%n_elements), source=0.0_rk)
            do e = 1, this%n_elements
                associate (rod => this%rods(this%element_rod(e)))
                    if (rod%dragged) call element_mass(this%element_length(e), rod%drag, &
                        rod%angular_drag, this%drag_matrix(:, :, e))
                end associate
            end do
        end if
        select case (this%scheme)
        case (scheme_ph_em)
            this%n_history = 3
        case (scheme_ph_irreducible)
            this%n_history = 2 * this%n_gauss
        case default
            this%n_history = 0
        end select
        this%n_y = this%n_free
        if (this%scheme == scheme_ph_em .and. .not. this%condensed) &
            this%n_y = this%n_free + 3 * this%n_elements
        call build_pattern(this)
        call find_angles(this)
        allocate(this%q_1(this%n_q), this%f_ext(this%n_q), this%f_rod(this%n_q, size(this%rods)))
        call set_initial_state(this, scene, rods)
    end subroutine planar_init

    !> The straight rods at rest or in rigid motion (methods §3.1, §6): nodes along the rod,
    !> theta_0 from its direction, elastic strains zero, or (1 - axial_reference, 0, 0) for a
    !> prestrained rod (the axial strain of its given length over its stress-free one,
    !> docs/theory/prestretched_starts.md) in the history of PH-EM (per element) and PH-EMi
    !> (per Gauss point); v = velocity + omega x (x -
    !> rotation_center) and theta' = omega . normal. A shared node takes the values of the
    !> first rod that reaches it (joined rods agree there by the input check). Then every
    !> element's reference stretch (reference_stretches) from these nodal coordinates, so that
    !> the given rod is stress-free to the last bit (prestrained: its stress-free state is it
    !> shortened by axial_reference; docs/theory/ph_planar.md "The reference stretch").
    subroutine set_initial_state(this, scene, rods)
        type(ph_planar_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:)
        real(rk) :: p(3), v(3), t(3), q0(6)
        logical :: done(this%n_q)
        integer :: r, k, e, at, stride
        allocate(this%initial(this%n_state()), source=0.0_rk)
        ! The axial strain is the first of each element's or Gauss point's history entries
        ! (PH-EM: Gamma1, Gamma2, kappa; PH-EMi: (Gamma1, Gamma2) per point).
        if (this%n_history > 0) then
            stride = merge(3, 2, this%scheme == scheme_ph_em)
            do e = 1, this%n_elements
                at = 2 * this%n_q + this%n_history * (e - 1)
                this%initial(at + 1:at + this%n_history:stride) = &
                    1.0_rk - this%rods(this%element_rod(e))%axial_reference
            end do
        end if
        done = .false.
        do r = 1, size(rods)
            associate (input => scene%rods(rods(r)), rod => this%rods(r))
                t = input%direction / norm2(input%direction)
                do k = 1, rod%n_elements + 1
                    p = input%start + rod%length * real(k - 1, rk) / real(rod%n_elements, rk) * t
                    v = input%velocity + cross(input%angular_velocity, p - input%rotation_center)
                    if (.not. done(rod%dofs(1, k))) then
                        this%initial(rod%dofs(1:2, k)) = point_in_plane(this%plane, p)
                        this%initial(this%n_q + rod%dofs(1:2, k)) = vector_in_plane(this%plane, v)
                        done(rod%dofs(1:2, k)) = .true.
                    end if
                    if (.not. done(rod%dofs(3, k))) then
                        this%initial(rod%dofs(3, k)) = rod%theta0
                        this%initial(this%n_q + rod%dofs(3, k)) = dot_product( &
                            input%angular_velocity, this%plane%normal)
                        done(rod%dofs(3, k)) = .true.
                    end if
                end do
            end associate
        end do
        ! With its own rod's theta_0 at both nodes: a rigid joint gives the joined rod the first
        ! rod's angle at the shared node, and a rod joined at an angle keeps that kink as a
        ! strain, as before the reference stretch (its curvature has no reference either).
        allocate(this%reference(2, this%n_gauss, this%n_elements))
        do e = 1, this%n_elements
            associate (rod => this%rods(this%element_rod(e)))
                q0 = this%initial(this%element_dofs(:, e))
                q0(3:6:3) = rod%theta0
                call reference_stretches(this%element_length(e), this%n_gauss, q0, &
                    rod%axial_reference, this%reference(:, :, e))
            end associate
        end do
    end subroutine set_initial_state

    !> Mesh, section and frame of one straight rod (methods §3.1): EA, the in-plane shear
    !> stiffness and the bending stiffness about the plane normal. The director along the normal
    !> (d1 or d2) names them: bending about d_k is EI_k and rhoI_k, in-plane shear is along the
    !> other director; their Kelvin-Voigt times likewise. Drag and angular drag as given. The
    !> same per element from `properties` (rs_model_scene element_properties).
    subroutine build_rod(this, input, properties, rod)
        type(ph_planar_t), intent(in) :: this
        type(rod_input_t), intent(in) :: input
        real(rk), intent(in) :: properties(:, :)
        type(planar_rod_t), intent(out) :: rod
        real(rk) :: t(3), d1(3), d2(3), n(3), shear_axis(3), tau(3)
        ! Indices into properties (EA, GA1, GA2, EI1, EI2, GJ, rhoA, rhoI1, rhoI2) of
        ! (EA, GA, EI) and rhoI.
        integer :: picked(3), inertia
        n = this%plane%normal
        t = input%direction / norm2(input%direction)
        d1 = input%d1
        d2 = cross(t, d1)
        rod%name = trim(input%name)
        rod%n_elements = input%n_elements
        rod%length = input%length
        rod%theta0 = angle_in_plane(this%plane, t)
        rod%axial_reference = axial_reference(input)
        rod%directors0(:, 1) = d1
        rod%directors0(:, 2) = d2
        rod%directors0(:, 3) = t
        ! The Kelvin-Voigt times follow their stiffnesses (&rod kelvin_voigt_time is in the order
        ! EA, GA1, GA2, EI1, EI2, GJ; torsion does not arise in the plane).
        if (abs(dot_product(d1, n)) > 0.5_rk) then
            rod%stiffness = [input%EA, input%GA2, input%EI1]
            rod%rho_i = input%rhoI1
            tau = input%kelvin_voigt_time([kv_axial, kv_shear2, kv_bend1])
            picked = [1, 3, 4]
            inertia = 8
        else
            rod%stiffness = [input%EA, input%GA1, input%EI2]
            rod%rho_i = input%rhoI2
            tau = input%kelvin_voigt_time([kv_axial, kv_shear1, kv_bend2])
            picked = [1, 2, 5]
            inertia = 9
        end if
        rod%rho_a = input%rhoA
        ! An unresolved scene (built in code) has no Kelvin-Voigt times.
        where (tau == unset_real) tau = 0.0_rk
        rod%viscosity = tau * rod%stiffness
        rod%drag = input%drag
        rod%angular_drag = input%angular_drag
        rod%viscous = any(rod%viscosity /= 0.0_rk)
        rod%dragged = rod%drag /= 0.0_rk .or. rod%angular_drag /= 0.0_rk
        rod%element_stiffness = properties(picked, :)
        rod%element_viscosity = spread(tau, 2, size(properties, 2)) * rod%element_stiffness
        rod%element_line_mass = properties(7, :)
        rod%element_rho = properties([7, inertia], :)
        if (this%quasistatic) then
            rod%rho_a = 0.0_rk
            rod%rho_i = 0.0_rk
            rod%element_rho = 0.0_rk
        end if
        ! Planar N1 (axial) is N3 along d3; planar N2 acts along the in-plane transverse
        ! direction n x t; the moment acts about n.
        shear_axis = cross(n, t)
        rod%stress_map = 0.0_rk
        rod%stress_map(3, 1) = 1.0_rk
        rod%stress_map(1, 2) = dot_product(d1, shear_axis)
        rod%stress_map(2, 2) = dot_product(d2, shear_axis)
        rod%stress_map(4, 3) = dot_product(d1, n)
        rod%stress_map(5, 3) = dot_product(d2, n)
    end subroutine build_rod

    !> Nodal unknowns: a position (x, y) per distinct point, an angle per distinct rotation.
    !> Joint ends share their position (revolute) or position and angle (rigid).
    subroutine number_dofs(this, scene, rods)
        type(ph_planar_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:)
        integer :: r, k, next
        do r = 1, size(this%rods)
            allocate(this%rods(r)%dofs(3, this%rods(r)%n_elements + 1), source=0)
        end do
        next = 0
        do r = 1, size(this%rods)
            associate (rod => this%rods(r))
                do k = 1, rod%n_elements + 1
                    if (rod%dofs(1, k) == 0) then
                        rod%dofs(1:2, k) = [next + 1, next + 2]
                        next = next + 2
                        call share(r, k, 1)
                    end if
                    if (rod%dofs(3, k) == 0) then
                        rod%dofs(3, k) = next + 1
                        next = next + 1
                        call share(r, k, 3)
                    end if
                end do
            end associate
        end do
        this%n_q = next
    contains
        !> Give every end joined to end (r, k) the unknowns `what` (1: position, 3: angle) of
        !> (r, k), following chains of joints.
        recursive subroutine share(r0, k0, what)
            integer, intent(in) :: r0, k0, what
            integer :: other, other_node, j, a, b, end_a, end_b
            if (.not. allocated(scene%joints)) return
            do j = 1, size(scene%joints)
                associate (joint => scene%joints(j))
                    if (what == 3 .and. trim(joint%kind) /= 'rigid') cycle
                    a = slot_of(joint%rod_a)
                    b = slot_of(joint%rod_b)
                    if (a == 0 .or. b == 0) cycle
                    end_a = end_node(a, joint%end_a)
                    end_b = end_node(b, joint%end_b)
                    if (a == r0 .and. end_a == k0) then
                        other = b
                        other_node = end_b
                    else if (b == r0 .and. end_b == k0) then
                        other = a
                        other_node = end_a
                    else
                        cycle
                    end if
                    if (this%rods(other)%dofs(what, other_node) /= 0) cycle
                    if (what == 1) then
                        this%rods(other)%dofs(1:2, other_node) = this%rods(r0)%dofs(1:2, k0)
                    else
                        this%rods(other)%dofs(3, other_node) = this%rods(r0)%dofs(3, k0)
                    end if
                    call share(other, other_node, what)
                end associate
            end do
        end subroutine share

        integer function slot_of(name)
            character(len=*), intent(in) :: name
            integer :: i
            slot_of = 0
            do i = 1, size(rods)
                if (trim(scene%rods(rods(i))%name) == trim(name)) slot_of = i
            end do
        end function slot_of

        integer function end_node(slot, which)
            integer, intent(in) :: slot
            character(len=*), intent(in) :: which
            end_node = merge(1, this%rods(slot)%n_elements + 1, trim(which) == 'start')
        end function end_node
    end subroutine number_dofs

    !> The q indices of the nodal angles, each once (joined rods share some), and whether they
    !> may be shifted by 2 pi k after a step: in dynamics, when no support fixes an angle.
    subroutine find_angles(this)
        type(ph_planar_t), intent(inout) :: this
        logical :: is_angle(this%n_q)
        integer :: r, i
        is_angle = .false.
        do r = 1, size(this%rods)
            is_angle(this%rods(r)%dofs(3, :)) = .true.
        end do
        this%theta_dofs = pack([(i, i = 1, this%n_q)], is_angle)
        this%wrap_theta = .not. this%quasistatic .and. all(this%unknown_of(this%theta_dofs) > 0)
        this%theta_shift = 0.0_rk
    end subroutine find_angles

    !> Supports (methods §6.2, §6.3) fix the planar coordinates they hold (rs_model_support
    !> mapped to the plane by planar_held): clamped x, y, theta of the end node, pinned x, y,
    !> sliding (a prismatic support, issue 26 item 3) theta and the coordinate across its axis,
    !> held the planar coordinates its held directions fix (and theta with the rotation). The
    !> remaining unknowns are numbered in q order.
    subroutine fix_supports(this, scene, rods, err)
        type(ph_planar_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:)
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: message
        logical :: fixed(this%n_q), held(3), ok
        real(rk) :: release(this%n_q)
        integer :: i, r, node, next
        fixed = .false.
        release = unset_real
        do i = 1, size(scene%bcs)
            associate (bc => scene%bcs(i))
                do r = 1, size(rods)
                    if (trim(scene%rods(rods(r))%name) /= trim(bc%rod)) cycle
                    node = merge(1, this%rods(r)%n_elements + 1, trim(bc%end) == 'start')
                    select case (trim(bc%kind))
                    case ('clamped', 'pinned', 'sliding', 'held', 'free')
                    case default
                        message = 'rod ''' // trim(bc%rod) // ''': a ''' // trim(bc%kind) // &
                            ''' end is not available for ' // this%formulation_name // &
                            ' (docs/user/capabilities.md)'
                        RS_SET_ERROR(err, 'ph_planar%init', message)
                        return
                    end select
                    call planar_held(this%plane, end_hold(bc), held, ok)
                    ! A slide along the plane normal would hold x and y: refused like an
                    ! oblique one.
                    if (trim(bc%kind) == 'sliding') ok = planar_coordinate_axis(this%plane, &
                        bc%axis) > 0
                    if (.not. ok .and. any(bc%hold == 'twist')) then
                        message = twist_hold_refusal(trim(bc%rod), this%formulation_name)
                        RS_SET_ERROR(err, 'ph_planar%init', message)
                        return
                    else if (.not. ok) then
                        message = 'rod ''' // trim(bc%rod) // ''': ' // this%formulation_name // &
                            ' holds the planar coordinates x, y (along e1 = (' // &
                            vector_text(this%plane%e1) // '), e2 = (' // &
                            vector_text(this%plane%e2) // ')), so '
                        if (trim(bc%kind) == 'sliding') then
                            message = message // 'a sliding end''s axis must be one of them; ' // &
                                'axis = (' // vector_text(bc%axis) // ')'
                        else
                            message = message // 'the directions a held end holds must lie ' // &
                                'along one of them or span the plane; hold = ' // hold_list(bc)
                        end if
                        RS_SET_ERROR(err, 'ph_planar%init', message)
                        return
                    end if
                    fixed(this%rods(r)%dofs(:, node)) = held
                    where (held) release(this%rods(r)%dofs(:, node)) = bc%release_time
                end do
            end associate
        end do
        ! A released support's coordinates are unknowns (held rows until the release).
        this%released_q = pack([(i, i = 1, this%n_q)], fixed .and. release /= unset_real)
        this%released_time = release(this%released_q)
        fixed(this%released_q) = .false.
        allocate(this%unknown_of(this%n_q), source=0)
        next = 0
        do i = 1, this%n_q
            if (fixed(i)) cycle
            next = next + 1
            this%unknown_of(i) = next
        end do
        this%n_free = next
    end subroutine fix_supports

    !> End loads, distributed loads and gravity of the system's rods, in planar components: an
    !> in-plane force and the moment about the plane normal (methods §3.4).
    subroutine read_loads(this, scene, rods, err)
        type(ph_planar_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:)
        type(error_t), allocatable, intent(out) :: err
        type(planar_load_t) :: load
        integer :: i, r, n
        n = 0
        allocate(this%loads(size(scene%loads) * size(rods)))
        do i = 1, size(scene%loads)
            associate (input => scene%loads(i))
                do r = 1, size(rods)
                    if (.not. load_applies_to(input, scene%rods(rods(r))%name)) cycle
                    load = planar_load_t()
                    load%rod = r
                    call time_function_from_load(input, load%factor, err)
                    RS_RETURN_IF_ERROR(err)
                    select case (trim(input%where))
                    case ('start')
                        load%node = 1
                    case ('end')
                        load%node = this%rods(r)%n_elements + 1
                    case default
                        load%node = 0
                    end select
                    if (trim(input%where) == 'gravity') then
                        ! Times each element's mass as given (element_line_mass), not the
                        ! (zero) quasistatic inertia.
                        load%force = vector_in_plane(this%plane, input%acceleration)
                        load%gravity = .true.
                    else
                        load%force = vector_in_plane(this%plane, input%force)
                        load%moment = dot_product(input%moment, this%plane%normal)
                    end if
                    n = n + 1
                    this%loads(n) = load
                end do
            end associate
        end do
        this%loads = this%loads(1:n)
    end subroutine read_loads

    !> The Jacobian pattern: the element couplings (q_a, q_b, strains), and per element where
    !> each local entry goes.
    subroutine build_pattern(this)
        type(ph_planar_t), intent(inout) :: this
        type(csr_builder_t) :: builder
        integer :: e, i, j, n_local
        integer, allocatable :: local(:)
        n_local = merge(9, 6, this%scheme == scheme_ph_em .and. .not. this%condensed)
        allocate(local(n_local))
        call builder%init(this%n_y, this%n_elements * n_local**2)
        do e = 1, this%n_elements
            call local_unknowns(this, e, local)
            call builder%add_block(local, local)
        end do
        call builder%build(this%pattern)
        call this%held%init(this%unknown_of(this%released_q), this%released_q, &
            this%released_time, this%pattern%row_ptr, this%pattern%cols)
        allocate(this%element_map(n_local, n_local, this%n_elements), source=0)
        do e = 1, this%n_elements
            call local_unknowns(this, e, local)
            do j = 1, n_local
                if (local(j) <= 0) cycle
                do i = 1, n_local
                    if (local(i) <= 0) cycle
                    this%element_map(i, j, e) = this%pattern%position(local(i), local(j))
                end do
            end do
        end do
    end subroutine build_pattern

    !> Indices into Y of element e's local unknowns (0 for a fixed one).
    pure subroutine local_unknowns(this, e, local)
        type(ph_planar_t), intent(in) :: this
        integer, intent(in) :: e
        integer, intent(out) :: local(:)
        integer :: i
        do i = 1, 6
            local(i) = this%unknown_of(this%element_dofs(i, e))
        end do
        if (size(local) == 9) local(7:9) = this%n_free + 3 * (e - 1) + [1, 2, 3]
    end subroutine local_unknowns

    ! ---- Sizes and state --------------------------------------------------------------------

    !> The nodal coordinates q (x_n(1:n_q)), for adaptive steps. Not the velocities: the update
    !> sets v_{n+1} = 2 (q_{n+1} - q_n)/h - v_n (methods/ph_planar.md §4.3), which keeps an
    !> undamped (-1)^n component no coordinate sees; weighed, it made every step of the planar
    !> spaghetti look wrong and drove the steps below Newton's reach. Nor the strain history,
    !> nor the angles theta when the update wraps them by 2 pi (wrap_theta: a jump, and a
    !> rejection cascade at t = 4.16 on the spinning spaghetti); their error shows in the
    !> positions of the nodes next to them.
    subroutine planar_error_entries(this, weigh)
        class(ph_planar_t), intent(in) :: this
        logical, intent(out) :: weigh(:)
        weigh = .false.
        weigh(1:this%n_q) = .true.
        if (this%wrap_theta) weigh(this%theta_dofs) = .false.
    end subroutine planar_error_entries

    pure integer function planar_n_state(this)
        class(ph_planar_t), intent(in) :: this
        planar_n_state = 2 * this%n_q + this%n_history * this%n_elements
    end function planar_n_state

    pure integer function planar_n_unknown(this)
        class(ph_planar_t), intent(in) :: this
        planar_n_unknown = this%n_y
    end function planar_n_unknown

    subroutine planar_jacobian_pattern(this, row_ptr, cols)
        class(ph_planar_t), intent(in) :: this
        integer, allocatable, intent(out) :: row_ptr(:), cols(:)
        call this%pattern%zero_based(row_ptr, cols)
    end subroutine planar_jacobian_pattern

    subroutine planar_initial_state(this, x)
        class(ph_planar_t), intent(in) :: this
        real(rk), intent(out) :: x(:)
        x = this%initial
    end subroutine planar_initial_state

    !> The nodal unknowns q_{n+1}: Y's entries where free, q_n where a support fixes them.
    pure subroutine full_q(this, q_n, y, q)
        class(ph_planar_t), intent(in) :: this
        real(rk), intent(in) :: q_n(:), y(:)
        real(rk), intent(out) :: q(:)
        integer :: i
        do i = 1, this%n_q
            if (this%unknown_of(i) > 0) then
                q(i) = y(this%unknown_of(i))
            else
                q(i) = q_n(i)
            end if
        end do
    end subroutine full_q

    !> The first iterate: q_{n+1} = q_n and the strains of t_n (methods §4.6, as the authors).
    subroutine planar_predictor(this, t_n, h, x_n, y)
        class(ph_planar_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:)
        real(rk), intent(out) :: y(:)
        integer :: i
        do i = 1, this%n_q
            if (this%unknown_of(i) > 0) y(this%unknown_of(i)) = x_n(i)
        end do
        if (this%n_y > this%n_free) y(this%n_free + 1:) = x_n(2 * this%n_q + 1:)
    end subroutine planar_predictor

    !> X_{n+1}: q from Y, v_{n+1} = 2 (q_{n+1} - q_n) / h - v_n (the midpoint rule, methods §4.3;
    !> zero in a quasistatic run, which has no velocities, and after an equilibrium solve), and
    !> the element history. Then, when
    !> allowed (find_angles), every nodal angle is shifted by the same 2 pi k that brings the
    !> first one into [-pi, pi]: velocities and history come from the unshifted step.
    subroutine planar_update(this, t_n, h, x_n, y, x_1)
        class(ph_planar_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: x_1(:)
        integer :: e, first
        call this%full_q(x_n(1:this%n_q), y, x_1(1:this%n_q))
        if (this%quasistatic .or. this%static) then
            ! No velocities in a quasistatic run; an equilibrium (the initial one of a dynamic
            ! run, &time initial_equilibrium) is at rest.
            x_1(this%n_q + 1:2 * this%n_q) = 0.0_rk
        else
            x_1(this%n_q + 1:2 * this%n_q) = 2.0_rk * (x_1(1:this%n_q) - x_n(1:this%n_q)) / h - &
                x_n(this%n_q + 1:2 * this%n_q)
        end if
        if (this%n_history > 0) then
            first = 2 * this%n_q
            do e = 1, this%n_elements
                call this%element_strains(e, h, x_n, x_1(1:this%n_q), y, &
                    x_1(first + this%n_history * (e - 1) + 1:first + this%n_history * e))
            end do
        end if
        this%theta_shift = 0.0_rk
        if (this%wrap_theta) then
            this%theta_shift = 2.0_rk * pi * anint(x_1(this%theta_dofs(1)) / (2.0_rk * pi))
            if (this%theta_shift /= 0.0_rk) &
                x_1(this%theta_dofs) = x_1(this%theta_dofs) - this%theta_shift
        end if
    end subroutine planar_update

    !> Element e's history at t_{n+1}: the mixed strains (from Y, or the condensed update of
    !> methods eqs. 63-64) or the Gauss-point strains of PH-EMi (methods eq. 78).
    subroutine element_strains(this, e, h, x_n, q_1, y, hist)
        class(ph_planar_t), intent(in) :: this
        integer, intent(in) :: e
        real(rk), intent(in) :: h, x_n(:), q_1(:), y(:)
        real(rk), intent(out) :: hist(:)
        real(rk) :: q_n6(6), q_16(6), r6(6), k6(6, 6), gamma_n(2, 2), gammas(2, 2), gammas3(3, 2)
        integer :: at, p
        q_n6 = x_n(this%element_dofs(:, e))
        q_16 = q_1(this%element_dofs(:, e))
        at = 2 * this%n_q + this%n_history * (e - 1)
        if (this%static) then
            ! An equilibrium: the strains of the state itself (ph_em_static, cl_em_static).
            call compatible_strains(this%element_length(e), this%n_gauss, q_16, &
                gammas3(:, 1:this%n_gauss), this%reference(:, :, e))
            select case (this%scheme)
            case (scheme_ph_em)
                if (this%condensed) then
                    hist = ph_em_projected_strains(this%element_length(e), this%n_gauss, q_16, &
                        this%reference(:, :, e))
                else
                    hist = y(this%n_free + 3 * (e - 1) + 1:this%n_free + 3 * e)
                end if
            case (scheme_ph_irreducible)
                do p = 1, this%n_gauss
                    hist(2 * p - 1:2 * p) = gammas3(1:2, p)
                end do
            end select
            return
        end if
        select case (this%scheme)
        case (scheme_ph_em)
            if (this%condensed) then
                associate (rod => this%rods(this%element_rod(e)))
                    call ph_em_condensed(this%element_length(e), this%stiffness(:, e), this%viscosity(:, e), &
                        this%n_gauss, h, q_n6, q_16, x_n(at + 1:at + 3), r6, k6, hist)
                end associate
            else
                hist = y(this%n_free + 3 * (e - 1) + 1:this%n_free + 3 * e)
            end if
        case (scheme_ph_irreducible)
            call history_at_gauss_points(this, x_n, at, gamma_n)
            call ph_emi_strains(this%element_length(e), this%n_gauss, q_n6, q_16, &
                gamma_n(:, 1:this%n_gauss), gammas(:, 1:this%n_gauss))
            do p = 1, this%n_gauss
                hist(2 * p - 1:2 * p) = gammas(:, p)
            end do
        end select
    end subroutine element_strains

    !> The Gauss-point strains of PH-EMi stored in x from position at + 1 (methods eq. 78).
    pure subroutine history_at_gauss_points(this, x, at, gammas)
        class(ph_planar_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        integer, intent(in) :: at
        real(rk), intent(out) :: gammas(2, 2)
        integer :: p
        gammas = 0.0_rk
        do p = 1, this%n_gauss
            gammas(:, p) = x(at + 2 * p - 1:at + 2 * p)
        end do
    end subroutine history_at_gauss_points

    ! ---- The step problem -------------------------------------------------------------------

    !> F(Y): per free nodal unknown the time-discrete momentum balance, inertia M (v_{n+1} -
    !> v_n) / h plus internal forces minus loads at t_{n+1/2} (methods §4.3); per element of an
    !> uncondensed PH-EM system its strain rows (scaled by 1/h as the authors, so that the
    !> Newton norm is theirs, methods §4.6).
    subroutine planar_step_residual(this, t_n, h, x_n, y, f, status)
        class(ph_planar_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: f(:)
        integer, intent(out) :: status
        call residual_values(this, t_n, h, x_n, y, size(f), f)
        status = state_valid
        if (has_nan(size(f), f)) status = state_invalid
    end subroutine planar_step_residual

    ! The rows of planar_step_residual, on an explicit-shape f (as jacobian_values).
    subroutine residual_values(this, t_n, h, x_n, y, n_f, f)
        type(ph_planar_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        integer, intent(in) :: n_f
        real(rk), intent(out) :: f(n_f)
        real(rk) :: r9(9), k6(6, 6), e_1(3), q_n6(6), q_16(6), v_n6(6), gamma_n(2, 2)
        integer :: e, i, at, row, dofs(6)
        if (this%static) then
            call static_rows(this, t_n + h, merge(this%row_scale, h, this%continuing), x_n, y, &
                n_f, f=f)
            return
        end if
        f = 0.0_rk
        call this%full_q(x_n(1:this%n_q), y, this%q_1)
        do e = 1, this%n_elements
            ! A fixed-size copy: index expressions on the section allocated a temporary.
            dofs = this%element_dofs(:, e)
            associate (rod => this%rods(this%element_rod(e)), le => this%element_length(e))
                q_n6 = x_n(dofs)
                q_16 = this%q_1(dofs)
                at = 2 * this%n_q + this%n_history * (e - 1)
                ! Every branch sets r9(1:6); r9(7:9) only matters for uncondensed PH-EM.
                select case (this%scheme)
                case (scheme_ph_em)
                    if (this%condensed) then
                        call ph_em_condensed(le, this%stiffness(:, e), this%viscosity(:, e), this%n_gauss, h, &
                            q_n6, q_16, x_n(at + 1:at + 3), r9(1:6), k6, e_1)
                    else
                        row = this%n_free + 3 * (e - 1)
                        call ph_em_residual(le, this%stiffness(:, e), this%viscosity(:, e), this%n_gauss, h, &
                            q_n6, q_16, x_n(at + 1:at + 3), y(row + 1:row + 3), r9)
                        f(row + 1:row + 3) = r9(7:9)
                    end if
                case (scheme_stander_stein)
                    call cl_em_residual(le, this%stiffness(:, e), this%viscosity(:, e), this%n_gauss, h, q_n6, &
                        q_16, r9(1:6), this%reference(:, :, e))
                case (scheme_ph_irreducible)
                    call history_at_gauss_points(this, x_n, at, gamma_n)
                    call ph_emi_residual(le, this%stiffness(:, e), this%viscosity(:, e), this%n_gauss, h, q_n6, &
                        q_16, gamma_n(:, 1:this%n_gauss), r9(1:6))
                end select
                if (.not. this%quasistatic) then
                    v_n6 = x_n(this%n_q + dofs)
                    r9(1:6) = r9(1:6) + mass_times(this%mass(:, :, e), &
                        2.0_rk * (q_16 - q_n6) / h - 2.0_rk * v_n6) / h
                end if
                ! Drag against the step's midpoint velocity v_mid = (q_1 - q_n)/h.
                if (rod%dragged) r9(1:6) = r9(1:6) + mass_times(this%drag_matrix(:, :, e), &
                    (q_16 - q_n6) / h)
                do i = 1, 6
                    row = this%unknown_of(dofs(i))
                    if (row > 0) f(row) = f(row) + r9(i)
                end do
            end associate
        end do
        call this%load_vectors(t_n + 0.5_rk * h)
        do i = 1, this%n_q
            if (this%unknown_of(i) > 0) f(this%unknown_of(i)) = f(this%unknown_of(i)) - this%f_ext(i)
        end do
        call this%held%apply_residual(t_n, h, .false., x_n, y, f)
    end subroutine residual_values

    !> dF/dY: the element tangents (methods §10: analytic, checked against finite differences in
    !> tests/unit/formulations/test_planar_element) plus (2 / h^2) M in the nodal block.
    !> The equilibrium rows at load time t_static (the endpoint or initial equilibrium of a
    !> quasistatic run, DESIGN.md §3): per free nodal unknown the internal force of the state
    !> minus the load, per element of uncondensed PH-EM its non-rate strain rows scaled as a step
    !> of length `scale` (ph_em_static; cl-EM and PH-EMi: cl_em_static). In a continuation the
    !> rows at its start are subtracted with the weight 1 - tau. Either the residual f or the
    !> Jacobian values (of the same CSR pattern as a step).
    subroutine static_rows(this, tau, scale, x_n, y, n, f, values)
        type(ph_planar_t), intent(inout) :: this
        real(rk), intent(in) :: tau, scale, x_n(:), y(:)
        integer, intent(in) :: n
        real(rk), intent(out), optional :: f(n), values(n)
        real(rk) :: r9(9), k9(9, 9), e_1(3)
        integer :: e, i, j, row, n_local, dofs(6)
        if (present(f)) f = 0.0_rk
        if (present(values)) values = 0.0_rk
        n_local = size(this%element_map, 1)
        call this%full_q(x_n(1:this%n_q), y, this%q_1)
        do e = 1, this%n_elements
            dofs = this%element_dofs(:, e)
            row = this%n_free + 3 * (e - 1)
            associate (rod => this%rods(this%element_rod(e)), le => this%element_length(e))
                select case (this%scheme)
                case (scheme_ph_em)
                    if (this%condensed .and. present(values)) then
                        call ph_em_static_condensed(le, this%stiffness(:, e), this%n_gauss, &
                            this%q_1(dofs), r9(1:6), e_1, k9(1:6, 1:6), this%reference(:, :, e))
                    else if (this%condensed) then
                        call ph_em_static_condensed(le, this%stiffness(:, e), this%n_gauss, &
                            this%q_1(dofs), r9(1:6), e_1, reference=this%reference(:, :, e))
                    else if (present(values)) then
                        call ph_em_static(le, this%stiffness(:, e), this%n_gauss, scale, this%q_1(dofs), &
                            y(row + 1:row + 3), r9, k9, this%reference(:, :, e))
                    else
                        call ph_em_static(le, this%stiffness(:, e), this%n_gauss, scale, this%q_1(dofs), &
                            y(row + 1:row + 3), r9, reference=this%reference(:, :, e))
                        f(row + 1:row + 3) = r9(7:9)
                    end if
                case default
                    if (present(values)) then
                        call cl_em_static(le, this%stiffness(:, e), this%n_gauss, this%q_1(dofs), &
                            r9(1:6), k9(1:6, 1:6), this%reference(:, :, e))
                    else
                        call cl_em_static(le, this%stiffness(:, e), this%n_gauss, this%q_1(dofs), &
                            r9(1:6), reference=this%reference(:, :, e))
                    end if
                end select
            end associate
            if (present(values)) then
                do j = 1, n_local
                    do i = 1, n_local
                        if (this%element_map(i, j, e) > 0) values(this%element_map(i, j, e)) = &
                            values(this%element_map(i, j, e)) + k9(i, j)
                    end do
                end do
            else
                do i = 1, 6
                    if (this%unknown_of(dofs(i)) > 0) f(this%unknown_of(dofs(i))) = &
                        f(this%unknown_of(dofs(i))) + r9(i)
                end do
            end if
        end do
        if (.not. present(f)) then
            call this%held%apply_jacobian(this%t_static, 0.0_rk, .true., values)
            return
        end if
        call this%load_vectors(this%t_static)
        do i = 1, this%n_q
            if (this%unknown_of(i) > 0) &
                f(this%unknown_of(i)) = f(this%unknown_of(i)) - this%f_ext(i)
        end do
        if (this%continuing) f = f - max(0.0_rk, 1.0_rk - tau) * this%anchor
        call this%held%apply_residual(this%t_static, 0.0_rk, .true., x_n, y, f)
    end subroutine static_rows

    subroutine planar_step_jacobian(this, t_n, h, x_n, y, values, status)
        class(ph_planar_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: values(:)
        integer, intent(out) :: status
        call jacobian_values(this, t_n, h, x_n, y, size(values), values)
        status = state_valid
        if (has_nan(size(values), values)) status = state_invalid
    end subroutine planar_step_jacobian

    ! The CSR values of planar_step_jacobian, on an explicit-shape values: with the interface's
    ! values(:), of a stride unknown at compile time, zeroing and NaN-checking the 729 values of
    ! the 10-element spaghetti were strided scalar loops, a third of this routine's own time.
    subroutine jacobian_values(this, t_n, h, x_n, y, n_values, values)
        type(ph_planar_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        integer, intent(in) :: n_values
        real(rk), intent(out) :: values(n_values)
        real(rk) :: k9(9, 9), k6(6, 6), r6(6), e_1(3), q_n6(6), q_16(6), gamma_n(2, 2)
        integer :: e, i, j, at, row, n_local, dofs(6)
        if (this%static) then
            call static_rows(this, 1.0_rk, merge(this%row_scale, h, this%continuing), x_n, y, &
                n_values, values=values)
            return
        end if
        values = 0.0_rk
        n_local = size(this%element_map, 1)
        call this%full_q(x_n(1:this%n_q), y, this%q_1)
        do e = 1, this%n_elements
            dofs = this%element_dofs(:, e)
            associate (rod => this%rods(this%element_rod(e)), le => this%element_length(e))
                q_n6 = x_n(dofs)
                q_16 = this%q_1(dofs)
                at = 2 * this%n_q + this%n_history * (e - 1)
                ! Local arrays of fixed shape: no temporaries in the time loop. Every branch sets
                ! k9(1:n_local, 1:n_local), the part that is scattered.
                select case (this%scheme)
                case (scheme_ph_em)
                    if (this%condensed) then
                        call ph_em_condensed(le, this%stiffness(:, e), this%viscosity(:, e), this%n_gauss, h, &
                            q_n6, q_16, x_n(at + 1:at + 3), r6, k6, e_1)
                        k9(1:6, 1:6) = k6
                    else
                        row = this%n_free + 3 * (e - 1)
                        call ph_em_jacobian(le, this%stiffness(:, e), this%viscosity(:, e), this%n_gauss, h, &
                            q_n6, q_16, x_n(at + 1:at + 3), y(row + 1:row + 3), k9)
                    end if
                case (scheme_stander_stein)
                    call cl_em_jacobian(le, this%stiffness(:, e), this%viscosity(:, e), this%n_gauss, h, q_n6, &
                        q_16, k6, this%reference(:, :, e))
                    k9(1:6, 1:6) = k6
                case (scheme_ph_irreducible)
                    call history_at_gauss_points(this, x_n, at, gamma_n)
                    call ph_emi_jacobian(le, this%stiffness(:, e), this%viscosity(:, e), this%n_gauss, h, q_n6, &
                        q_16, gamma_n(:, 1:this%n_gauss), k6)
                    k9(1:6, 1:6) = k6
                end select
                if (.not. this%quasistatic) &
                    k9(1:6, 1:6) = k9(1:6, 1:6) + (2.0_rk / h**2) * this%mass(:, :, e)
                if (rod%dragged) k9(1:6, 1:6) = k9(1:6, 1:6) + this%drag_matrix(:, :, e) / h
                do j = 1, n_local
                    do i = 1, n_local
                        if (this%element_map(i, j, e) > 0) values(this%element_map(i, j, e)) = &
                            values(this%element_map(i, j, e)) + k9(i, j)
                    end do
                end do
            end associate
        end do
        call this%held%apply_jacobian(t_n, h, .false., values)
    end subroutine jacobian_values

    !> Nodal load vectors at time t: per rod (f_rod, for its work) and in total (f_ext).
    !> Distributed loads are consistent, int N_I nbar ds = nbar L_e / 2 per node (methods §3.4).
    subroutine load_vectors(this, t)
        class(ph_planar_t), intent(inout) :: this
        real(rk), intent(in) :: t
        real(rk) :: factor, half
        integer :: i, e, k, r
        this%f_rod = 0.0_rk
        do i = 1, size(this%loads)
            r = this%loads(i)%rod
            associate (load => this%loads(i), rod => this%rods(r))
                factor = load%factor%value(t)
                if (load%node > 0) then
                    k = load%node
                    this%f_rod(rod%dofs(1:2, k), r) = this%f_rod(rod%dofs(1:2, k), r) + &
                        factor * load%force
                    this%f_rod(rod%dofs(3, k), r) = this%f_rod(rod%dofs(3, k), r) + &
                        factor * load%moment
                else
                    do e = 1, rod%n_elements
                        half = 0.5_rk * factor * rod%length / real(rod%n_elements, rk)
                        if (load%gravity) half = half * rod%element_line_mass(e)
                        do k = e, e + 1
                            this%f_rod(rod%dofs(1:2, k), r) = this%f_rod(rod%dofs(1:2, k), r) + &
                                half * load%force
                            this%f_rod(rod%dofs(3, k), r) = this%f_rod(rod%dofs(3, k), r) + &
                                half * load%moment
                        end do
                    end do
                end if
            end associate
        end do
        this%f_ext = sum(this%f_rod, dim=2)
    end subroutine load_vectors

    ! ---- After a step: energy balance (methods §4.1, eq. 55) -------------------------------

    !> The energy terms of each rod over an accepted step: H_n, H_{n+1}, the work of its
    !> own loads at t_{n+1/2} and what its damping dissipated (rod_dissipation). The rods share
    !> unknowns at their joints, so only their sum balances (traits%shared_balance: the ledger
    !> books it on the first rod). An equilibrium solve is not a load step: no energy terms,
    !> and its h is not a step of the grid.
    subroutine planar_accept_step(this, t_n, h, x_n, x_1, terms)
        class(ph_planar_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), x_1(:)
        type(step_energy_t), intent(out) :: terms(:)
        real(rk) :: kinetic_n, strain_n, kinetic_1, strain_1, work
        integer :: r
        if (this%static) then
            terms = step_energy_t(reported=.false., grid_step=.false.)
            return
        end if
        call this%load_vectors(t_n + 0.5_rk * h)
        do r = 1, size(this%rods)
            call this%rod_energy(x_n, r, kinetic_n, strain_n)
            call this%rod_energy(x_1, r, kinetic_1, strain_1)
            ! The angles moved by x_1 - x_n plus the shift that update took away.
            work = dot_product(this%f_rod(:, r), x_1(1:this%n_q) - x_n(1:this%n_q)) + &
                this%theta_shift * sum(this%f_rod(this%theta_dofs, r))
            terms(r) = step_energy_t(reported=.true., before=kinetic_n + strain_n, &
                after=kinetic_1 + strain_1, work=work, &
                dissipated=this%rod_dissipation(h, x_n, x_1, r))
        end do
    end subroutine planar_accept_step

    !> Kinetic energy 1/2 v^T M v with the consistent mass and the strain energy of rod r
    !> (methods §4.3 "discrete diagnostics"): of the mixed strains (PH-EM), of the compatible
    !> strains with the scheme's quadrature (cl-EM) or of the Gauss-point strains (PH-EMi).
    !> Per rod, with scalar results: arrays over the rods sized at run time were allocated at
    !> every step (accept_step, record).
    subroutine rod_energy(this, x, r, kinetic, strain)
        class(ph_planar_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        integer, intent(in) :: r
        real(rk), intent(out) :: kinetic, strain
        real(rk) :: v6(6), q6(6), g(2, 2)
        integer :: e, at, dofs(6)
        kinetic = 0.0_rk
        strain = 0.0_rk
        associate (rod => this%rods(r))
            do e = rod%first_element, rod%first_element + rod%n_elements - 1
                dofs = this%element_dofs(:, e)
                associate (le => this%element_length(e))
                    q6 = x(dofs)
                    if (.not. this%quasistatic) then
                        v6 = x(this%n_q + dofs)
                        kinetic = kinetic + 0.5_rk * dot_product(v6, &
                            mass_times(this%mass(:, :, e), v6))
                    end if
                    at = 2 * this%n_q + this%n_history * (e - 1)
                    select case (this%scheme)
                    case (scheme_ph_em)
                        strain = strain + mixed_strain_energy(le, this%stiffness(:, e), x(at + 1:at + 3))
                    case (scheme_stander_stein)
                        strain = strain + compatible_strain_energy(le, this%stiffness(:, e), &
                            this%n_gauss, q6, this%reference(:, :, e))
                    case (scheme_ph_irreducible)
                        call history_at_gauss_points(this, x, at, g)
                        strain = strain + ph_emi_strain_energy(le, this%stiffness(:, e), &
                            this%n_gauss, q6, g(:, 1:this%n_gauss))
                    end select
                end associate
            end do
        end associate
    end subroutine rod_energy

    !> The energy D_n >= 0 that rod r's damping dissipated over the step of length h from x_n to
    !> x_1 (docs/theory/ph_planar.md "Damping"), per element:
    !> - Kelvin-Voigt: viscous_dissipation of the scheme's strain increments, those its viscous
    !>   stresses used: the mixed strains (PH-EM), the compatible strains at the Gauss points
    !>   (cl-EM), the Gauss-point history and the compatible curvature (PH-EMi);
    !> - drag: h v_mid^T C v_mid with v_mid = (v_n + v_{n+1})/2 = (q_{n+1} - q_n)/h (the midpoint
    !>   rule; unlike q_{n+1}, the velocities are not shifted by 2 pi k in update).
    !> Zero, at once, for an undamped rod. The step's residual rows make H_{n+1} - H_n = W - D_n
    !> up to the Newton tolerance.
    function rod_dissipation(this, h, x_n, x_1, r) result(dissipated)
        class(ph_planar_t), intent(in) :: this
        real(rk), intent(in) :: h, x_n(:), x_1(:)
        integer, intent(in) :: r
        real(rk) :: dissipated
        real(rk) :: v6(6), q6(6), delta(3, 2), strains_n(3, 2), strains_1(3, 2), history_n(2, 2)
        real(rk) :: history_1(2, 2), le
        integer :: e, at, ng, dofs(6)
        dissipated = 0.0_rk
        ng = this%n_gauss
        associate (rod => this%rods(r))
            if (.not. (rod%viscous .or. rod%dragged)) return
            do e = rod%first_element, rod%first_element + rod%n_elements - 1
                dofs = this%element_dofs(:, e)
                le = this%element_length(e)
                if (rod%dragged) then
                    v6 = 0.5_rk * (x_n(this%n_q + dofs) + x_1(this%n_q + dofs))
                    dissipated = dissipated + h * dot_product(v6, &
                        mass_times(this%drag_matrix(:, :, e), v6))
                end if
                if (.not. rod%viscous) cycle
                at = 2 * this%n_q + this%n_history * (e - 1)
                select case (this%scheme)
                case (scheme_ph_em)
                    delta(:, 1) = x_1(at + 1:at + 3) - x_n(at + 1:at + 3)
                    dissipated = dissipated + viscous_dissipation(le, this%viscosity(:, e), 1, h, &
                        delta(:, 1:1))
                    cycle
                case (scheme_stander_stein)
                    q6 = x_n(dofs)
                    call compatible_strains(le, ng, q6, strains_n(:, 1:ng))
                    q6 = x_1(dofs)
                    call compatible_strains(le, ng, q6, strains_1(:, 1:ng))
                    delta(:, 1:ng) = strains_1(:, 1:ng) - strains_n(:, 1:ng)
                case (scheme_ph_irreducible)
                    call history_at_gauss_points(this, x_n, at, history_n)
                    call history_at_gauss_points(this, x_1, at, history_1)
                    delta(1:2, 1:ng) = history_1(:, 1:ng) - history_n(:, 1:ng)
                    delta(3, 1:ng) = ((x_1(dofs(6)) - x_1(dofs(3))) - &
                        (x_n(dofs(6)) - x_n(dofs(3)))) / le
                end select
                dissipated = dissipated + viscous_dissipation(le, this%viscosity(:, e), ng, h, &
                    delta(:, 1:ng))
            end do
        end associate
    end function rod_dissipation

    ! ---- Output (DESIGN.md §7) ---------------------------------------------------------------

    subroutine planar_init_history(this, histories, capacity)
        class(ph_planar_t), intent(in) :: this
        type(rod_history_t), intent(inout), target :: histories(:)
        integer, intent(in) :: capacity
        integer :: r, k, e
        real(rk) :: le
        do r = 1, size(this%rods)
            associate (rod => this%rods(r))
                call histories(r)%init(rod%name, this%formulation_name, rod%n_elements + 1, &
                    rod%n_elements, capacity)
                le = rod%length / real(rod%n_elements, rk)
                histories(r)%mesh = [(le * real(k - 1, rk), k = 1, rod%n_elements + 1)]
                histories(r)%stress_mesh = [(le * (real(e, rk) - 0.5_rk), e = 1, rod%n_elements)]
                ! No orthonormality constraint to report. Dissipation (of the damping,
                ! rod_dissipation) and actuator work (zeros) stay, so that the energy balance
                ! reads the same for every rod (docs/user/output.md).
                deallocate(histories(r)%constraint_residual)
            end associate
        end do
    end subroutine planar_init_history

    !> Append the state at time t to every rod's history: 3D fields from the plane, stresses at
    !> the element midpoints (the P0 values), energies, momenta about the origin. The work,
    !> balance and Newton statistics are the record ledger's (rs_system_ledger).
    subroutine planar_record(this, histories, t, x)
        class(ph_planar_t), intent(inout) :: this
        type(rod_history_t), intent(inout), target :: histories(:)
        real(rk), intent(in) :: t, x(:)
        real(rk) :: kinetic, strain
        real(rk) :: q(3), v(3), alpha, cos_alpha, sin_alpha, d(3), n(3), p6(6), q6(6), planar(3)
        real(rk) :: gammas(3, 2), history(2, 2), linear(3), angular(3), centre(3), le
        integer :: r, k, i, e, rec, at, node, dofs(6), node_dofs(3)
        n = this%plane%normal
        do r = 1, size(this%rods)
            associate (rod => this%rods(r))
                rec = histories(r)%next_record()
                if (rec == 0) cycle
                call this%rod_energy(x, r, kinetic, strain)
                histories(r)%time(rec) = t
                do k = 1, rod%n_elements + 1
                    node_dofs = rod%dofs(:, k)
                    q = x(node_dofs)
                    v = x(this%n_q + node_dofs)
                    histories(r)%position(:, k, rec) = point_from_plane(this%plane, q(1:2))
                    histories(r)%velocity(:, k, rec) = vector_from_plane(this%plane, v(1:2))
                    alpha = q(3) - rod%theta0
                    cos_alpha = cos(alpha)
                    sin_alpha = sin(alpha)
                    do i = 1, 3
                        d = rotated(rod%directors0(:, i), n, cos_alpha, sin_alpha)
                        histories(r)%directors(:, i, k, rec) = d
                        histories(r)%director_velocity(:, i, k, rec) = v(3) * cross(n, d)
                    end do
                end do
                linear = 0.0_rk
                angular = 0.0_rk
                centre = 0.0_rk
                do e = 1, rod%n_elements
                    i = rod%first_element + e - 1
                    le = this%element_length(i)
                    dofs = this%element_dofs(:, i)
                    q6 = x(dofs)
                    at = 2 * this%n_q + this%n_history * (i - 1)
                    select case (this%scheme)
                    case (scheme_ph_em)
                        planar = x(at + 1:at + 3)
                    case (scheme_stander_stein)
                        call compatible_strains(le, this%n_gauss, q6, gammas(:, 1:this%n_gauss), &
                            this%reference(:, :, i))
                        planar = sum(gammas(:, 1:this%n_gauss), dim=2) / real(this%n_gauss, rk)
                    case default
                        call history_at_gauss_points(this, x, at, history)
                        planar(1:2) = sum(history(:, 1:this%n_gauss), dim=2) / real(this%n_gauss, rk)
                        planar(3) = (q6(6) - q6(3)) / le
                    end select
                    histories(r)%strains(:, e, rec) = matmul(rod%stress_map, planar)
                    histories(r)%stress(:, e, rec) = matmul(rod%stress_map, &
                        this%stiffness(:, rod%first_element + e - 1) * planar)
                    ! Momenta with the consistent mass (methods eq. 57): r x (M v) + (M v)_theta.
                    p6 = 0.0_rk
                    if (.not. this%quasistatic) &
                        p6 = mass_times(this%mass(:, :, i), x(this%n_q + dofs))
                    do node = 0, 1
                        linear = linear + vector_from_plane(this%plane, p6(3 * node + 1:3 * node + 2))
                        angular = angular + cross(point_from_plane(this%plane, &
                            q6(3 * node + 1:3 * node + 2)), vector_from_plane(this%plane, &
                            p6(3 * node + 1:3 * node + 2))) + p6(3 * node + 3) * n
                    end do
                    centre = centre + 0.5_rk * le * (point_from_plane(this%plane, q6(1:2)) + &
                        point_from_plane(this%plane, q6(4:5)))
                end do
                histories(r)%kinetic(rec) = kinetic
                histories(r)%strain(rec) = strain
                histories(r)%total(rec) = kinetic + strain
                histories(r)%linear_momentum(:, rec) = linear
                histories(r)%angular_momentum(:, rec) = angular
                histories(r)%center_of_mass(:, rec) = centre / rod%length
            end associate
        end do
    end subroutine planar_record

    function planar_describe(this) result(text)
        class(ph_planar_t), intent(in) :: this
        character(len=:), allocatable :: text
        character(len=:), allocatable :: names, scheme
        integer :: r
        names = this%rods(1)%name
        do r = 2, size(this%rods)
            names = names // '+' // this%rods(r)%name
        end do
        select case (this%scheme)
        case (scheme_ph_em)
            if (this%condensed) then
                scheme = 'PH-EM, strains condensed per element'
            else
                scheme = 'PH-EM, element strains as unknowns'
            end if
        case (scheme_stander_stein)
            scheme = 'Stander-Stein, ' // str(this%n_gauss) // '-point axial/shear quadrature'
        case default
            scheme = 'PH-EMi, strain history at ' // str(this%n_gauss) // ' Gauss points'
        end select
        text = 'rod ''' // names // ''': ' // this%formulation_name // ' (' // scheme // '), ' // &
            str(size(this%rods)) // ' rod(s), ' // str(this%n_elements) // ' elements, ' // &
            str(this%n_y) // ' Newton unknowns, ' // str(this%pattern%nnz()) // &
            ' Jacobian non-zeros'
    end function planar_describe

    ! ---- Quasistatics: the equilibrium solves (DESIGN.md §3) -----------------------------------

    !> The traits of the planar schemes:
    !> - energy: all three schemes are energy-consistent, H_{n+1} - H_n = W up to the Newton
    !>   tolerance (methods §4.3, Appendix A.5); a quasistatic run has no kinetic energy to
    !>   check;
    !> - quasistatic runs end with the endpoint equilibrium: the midpoint load steps (methods
    !>   §4.7) balance the loads at the mid times with rate-form strains, not at t_{n+1}; every
    !>   scheme continues it (static_rows has the unknowns of a step);
    !> - native LU: PETSc's own LU is safe without pivoting when every diagonal entry is
    !>   non-zero: the mass (2/h^2) M on the nodal block of a dynamic run, the stiffness of the
    !>   condensed element tangent. An uncondensed quasistatic Jacobian has zero (x, y)
    !>   diagonals (the nodal forces of PH-EM depend on the positions only through the
    !>   strains): the chain LU pivots there;
    !> - plain Newton, as the authors (methods §4.6): the paper's iteration counts are for the
    !>   full step, and backtracking multiplies the displacement schemes' iterations tenfold on
    !>   the four-bar (docs/performance.md);
    !> - shared balance: joined rods share the unknowns of their joints, so the joint forces
    !>   are not separable and only the sum of the rods' balances closes (one rod: the same).
    pure function planar_traits(this) result(traits)
        class(ph_planar_t), intent(in) :: this
        type(formulation_traits_t) :: traits
        traits%shared_balance = .true.
        traits%energy_scheme = merge(energy_unchecked, energy_consistent, this%quasistatic)
        traits%wants_endpoint_solve = this%quasistatic
        traits%continues_equilibrium = this%quasistatic
        traits%native_lu = .not. this%quasistatic .or. this%condensed .or. &
            this%scheme /= scheme_ph_em
        traits%full_newton = .true.
        ! Y = q_{n+1} (v eliminated, methods §4.3) and, uncondensed, the element strains, whose
        ! rows are algebraic at rest (docs/theory/modes.md). Every scheme: cl-EM's Z1 = cos(dphi
        ! / 2) and Z2 = sinc(dphi / 2) are smooth at rest, 1 with zero derivatives, so its step
        ! Jacobian there is 2 M / h^2 + K / 2 as well.
        if (.not. this%quasistatic) traits%modal_form = modal_second_order
    end function planar_traits

    !> The next steps solve the equilibrium at load time t_load (`endpoint`; static_rows), or
    !> are load steps again. With continue_from, the equilibrium is a continuation anchored
    !> there: the equilibrium rows of continue_from, for its own unknowns (the predictor's Y),
    !> are removed with the weight 1 - tau.
    subroutine planar_set_step_problem(this, endpoint, t_load, continue_from)
        class(ph_planar_t), intent(inout) :: this
        logical, intent(in) :: endpoint
        real(rk), intent(in) :: t_load
        real(rk), intent(in), optional :: continue_from(:)
        real(rk) :: y(this%n_y)
        this%static = endpoint
        this%t_static = t_load
        if (.not. endpoint) then
            this%continuing = .false.
            return
        end if
        if (.not. present(continue_from)) return
        this%row_scale = 1.0_rk
        call this%predictor(0.0_rk, this%row_scale, continue_from, y)
        if (allocated(this%anchor)) deallocate(this%anchor)
        allocate(this%anchor(this%n_y))
        this%continuing = .false.
        call static_rows(this, 1.0_rk, this%row_scale, continue_from, y, this%n_y, f=this%anchor)
        this%continuing = .true.
    end subroutine planar_set_step_problem

    !> The continuation's path weights (rod_formulation_t%path_weights): the free nodal x, y
    !> by 1 / L^2 (L the longest rod's length) and angles theta by 1, each over the number of
    !> nodal angles of the system; the strain unknowns 0.
    subroutine planar_path_weights(this, w)
        class(ph_planar_t), intent(in) :: this
        real(rk), intent(out) :: w(:)
        real(rk) :: nodes, length
        integer :: i
        w = 0.0_rk
        nodes = real(max(1, size(this%theta_dofs)), rk)
        length = maxval(this%rods(:)%length)
        do i = 1, this%n_q
            if (this%unknown_of(i) > 0) w(this%unknown_of(i)) = 1.0_rk / (length**2 * nodes)
        end do
        do i = 1, size(this%theta_dofs)
            if (this%unknown_of(this%theta_dofs(i)) > 0) &
                w(this%unknown_of(this%theta_dofs(i))) = 1.0_rk / nodes
        end do
    end subroutine planar_path_weights

    !> No kinetic energy is reported (no &time relaxation for the planar schemes); with
    !> `from`, the largest change of a nodal angle theta from `from` to x.
    function planar_state_measures(this, x, from) result(measures)
        class(ph_planar_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        real(rk), intent(in), optional :: from(:)
        type(state_measures_t) :: measures
        if (present(from)) &
            measures%largest_rotation = maxval(abs(x(this%theta_dofs) - from(this%theta_dofs)))
    end function planar_state_measures

    ! ---- Small helpers ----------------------------------------------------------------------

    !> m a for one element's mass m(6, 6); explicit shapes, so that the product is unrolled (on
    !> a section of the allocatable element masses it was a loop with a store per term).
    pure function mass_times(m, a) result(b)
        real(rk), intent(in) :: m(6, 6), a(6)
        real(rk) :: b(6)
        b = matmul(m, a)
    end function mass_times

    !> Whether a(1:n) holds a NaN (a failed evaluation, reported to the solver as such).
    pure logical function has_nan(n, a)
        integer, intent(in) :: n
        real(rk), intent(in) :: a(n)
        has_nan = any(a /= a)
    end function has_nan

    !> v rotated about the unit axis n by the angle whose cosine and sine are c and s
    !> (Rodrigues; the caller rotates the three directors of a node by one angle).
    pure function rotated(v, n, c, s) result(w)
        real(rk), intent(in) :: v(3), n(3), c, s
        real(rk) :: w(3)
        w = v * c + cross(n, v) * s + n * dot_product(n, v) * (1.0_rk - c)
    end function rotated

end module rs_ph_planar
