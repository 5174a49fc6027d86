#include "rs_macros.h"
!> The objective, locking-free SE(3) Petrov–Galerkin rod of seed 002 (methods/
!> se3_petrov_galerkin.md): two-node elements whose pose field is the relative twist of the
!> nodal poses scaled linearly (eq. 36), so the strains are constant per element (eq. 38), and
!> linear, independent test and velocity fields (eq. 41). The pure kernels are in
!> se3_pg_element.f90; this object assembles one rod.
!>
!> Unknowns per node (§5.1): q_i = (I r_i, psi_i), the position and the total rotation vector,
!> A_i = Exp(psi_i) with the K basis (e_x^K, e_y^K, e_z^K) = (d3, d1, d2) of rodsolve's
!> directors (d3 along the rod). Velocities u_i = (I v_i, K_i omega_i). After every accepted
!> step `update` replaces a rotation vector longer than pi (1.25 pi with generalized-alpha,
!> complement_angle) by its complement (eq. 40), never inside Newton; the step then starts
!> far from the singularities of T^{-1} at 2 pi k (docs/theory/se3_pg.md).
!>
!> Two step problems share the assembly:
!> - statics (&time quasistatic; methods §7.2): Newton on g_int(q) = f_ext(q, lambda) at the load
!>   factor lambda = t_{n+1}, the increments cut back by the stepper on failure and grown
!>   again on the remaining load;
!> - dynamics: q' = B(q) u, M u' = f_ext - g_int - f_gyr (eqs. 49-50) by one of two schemes of
!>   rs_formulations_generalized_alpha (&time scheme), both with the unknowns q_{n+1}:
!>   the implicit midpoint rule (methods §7.4), or the first-order generalized-alpha method of
!>   the paper (methods §7.3, Jansen, Whiting & Hulbert 2000) on y = (q, u). The stage rate
!>   q'_{n+alpha_m} and value q_{n+alpha_f} follow from q_{n+1} and the history; the kinematic
!>   equation at the stage, q'_{n+alpha_m} = B(q_{n+alpha_f}) u_{n+alpha_f}, gives the stage
!>   velocity, which is eliminated with u_{n+1} and u'_{n+alpha_m} (`stage_velocity`), so
!>   Newton solves the 6 equations of motion per free node at the stage,
!>   M u'_{n+alpha_m} + g_int(q_{n+alpha_f}) + f_gyr(u_{n+alpha_f}) = f_ext(q_{n+alpha_f},
!>   t_n + alpha_f h). The midpoint rule is the case alpha_m = alpha_f = gamma = 1/2, which
!>   reads no history. Neither keeps the energy of this nonlinear element exactly (§7.4):
!>   the balance error is reported and measured; generalized-alpha damps the high frequencies
!>   by design (docs/theory/se3_pg.md, "Generalized-alpha").
!>
!> State X: q = (r_k, psi_k) for the nodes k, then u = (v_k, omega_k); with generalized-alpha
!> also the history y'_n: q'_n = (r'_k, psi'_k), then u'_n = (v'_k, omega'_k), each 6 per node,
!> and with Kelvin-Voigt damping the strain rates eps'_n, 6 per element.
!>
!> Damping (&rod kelvin_voigt_time, drag, angular_drag; docs/theory/se3_pg.md "Damping",
!> docs/theory/damping.md): the Kelvin-Voigt stress V eps' of the objective element strains
!> eps = theta / l (methods eq. 38) is added to the elastic stress of g_int, eps' the scheme's
!> stage rate ((eps_{n+1} - eps_n) / h for the midpoint rule); the drag and angular drag are the
!> consistent matrix C_e on the stage velocities. D_n >= 0 is booked as dissipated.
!>
!> Supports eliminate unknowns (what each holds: rs_model_support): clamped fixes r and psi,
!> pinned fixes r (the heavy top's spherical joint), sliding and held the held coordinates of r
!> (and psi with the rotation, or its twist component alone: twist_coordinate), driven
!> prescribes r and psi (a clamp moved and turned in time,
!> e.g. the superimposed rotation of methods §10.3; rs_formulations_end_drive). Loads: dead
!> (spatial) and follower end forces and moments, dead distributed forces and moments,
!> gravity.
!>
!> The initial equilibrium of a dynamic run (&time initial_equilibrium; issue 26 item 3,
!> docs/theory/prestretched_starts.md): set_step_problem switches the same state layout to the
!> statics at the load time t = 0, continued from the initial placement (the Newton homotopy of
!> DESIGN.md §3, "Quasistatics"); its steps end at rest (u and the generalized-alpha history
!> zero, their values at a static equilibrium) and book no energy. A clamp or pin released at a
!> time (&bc release_time) keeps its coordinates as unknowns with held rows until then
!> (rs_formulations_held_rows).
module rs_se3_pg
    use rs_core_kinds, only: rk, pi
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: str, vector_text
    use rs_model_scene, only: scene_t, rod_input_t, bc_input_t, load_applies_to, element_properties, &
        axial_reference, unset_real
    use rs_model_rod_history, only: rod_history_t
    use rs_model_time_function, only: time_function_t, time_function_from_load
    use rs_model_support, only: end_hold_t, end_hold, held_coordinates, coordinate_hold_refusal
    use rs_formulations_end_drive, only: end_drive_t, end_drive_init
    use rs_model_rod_geometry, only: rod_geometry_t, rod_geometry_of, centreline_point, &
        centreline_frame
    use rs_math_so3, only: exp_so3, log_so3, hat, tangent_so3, tangent_so3_derivative, &
        complement_rotation_vector, nearest_rotation_vector
    use rs_math_se3, only: log_se3, pose_relative
    use rs_assembly_csr_pattern, only: csr_builder_t, csr_pattern_t
    use rs_formulations_formulation, only: rod_formulation_t, formulation_traits_t, state_valid, &
        state_invalid, rod_nodes_t, node_tie_t, state_measures_t, &
        step_energy_t, modal_second_order
    use rs_se3_pg_tie, only: se3_pg_node_tie_t, se3_pg_node_tie
    use rs_se3_pg_element, only: se3_strains, se3_internal_force, se3_internal_tangent, &
        se3_element_mass, se3_gyroscopic, follower_force, dead_moment, se3_strain_energy, &
        se3_mass_solve, se3_viscous_internal_force, se3_twist_tangent
    use rs_model_damping, only: kv_axial, kv_shear1, kv_shear2, kv_bend1, kv_bend2, kv_torsion
    use rs_formulations_generalized_alpha, only: generalized_alpha_t, generalized_alpha, &
        midpoint_scheme
    use rs_formulations_energy_sentinel, only: energy_dissipative
    use rs_formulations_held_rows, only: held_rows_t
    implicit none
    private

    !> An end load (node > 0) or a distributed load (node = 0), scaled by a time function.
    !> Dead loads in I components; follower loads in the node's K components.
    type :: se3_load_t
        integer :: node = 0
        logical :: follower = .false.
        !> Gravity: `force` is the acceleration, times each element's mass per length.
        logical :: gravity = .false.
        real(rk) :: force(3) = 0.0_rk
        real(rk) :: moment(3) = 0.0_rk
        type(time_function_t) :: factor
    end type se3_load_t

    type, extends(rod_formulation_t), public :: se3_pg_t
        character(len=:), allocatable :: name
        integer :: n_elements = 0, n_nodes = 0
        real(rk) :: length = 0.0_rk
        !> The current step problem is the statics: in a quasistatic run always, in a dynamic
        !> one during the initial equilibrium (static_stage; set_step_problem), whose loads and
        !> supports are those of the load time t_static, continued from the anchor's state
        !> (continuing: a step to the pseudo-time tau solves R(Y) = (1 - tau) anchor).
        logical :: statics = .false., quasistatic = .false., static_stage = .false.
        logical :: continuing = .false.
        real(rk) :: t_static = 0.0_rk
        real(rk), allocatable :: anchor(:)
        !> The time scheme of the dynamics: the midpoint rule, or generalized-alpha, whose
        !> history y'_n the state carries (methods §7.3).
        type(generalized_alpha_t) :: scheme
        !> Per element (&segment, issue 26 item 5): K-basis stiffnesses (EA, GA1, GA2, GJ, EI1,
        !> EI2), mass per length, K-basis inertia (rhoI1 + rhoI2, rhoI1, rhoI2) (methods §3.3,
        !> §3.5 with (x, y, z) = (d3, d1, d2)).
        real(rk), allocatable :: stiffness(:, :), rho_a(:), inertia(:, :)
        !> Damping (docs/theory/se3_pg.md, "Damping"): the Kelvin-Voigt viscosities tau_i k_i in
        !> the order of `stiffness`, the drag (force per length and velocity) and the angular
        !> drag (moment per length and angular velocity). `kelvin_voigt` and `dragged` say
        !> whether any is not zero: an undamped rod skips the terms. With generalized-alpha and
        !> Kelvin-Voigt, the state also carries the history of the strain rates, 6 per element.
        real(rk), allocatable :: viscosity(:, :)
        real(rk) :: drag = 0.0_rk, angular_drag = 0.0_rk
        logical :: kelvin_voigt = .false., dragged = .false.
        !> Per element: reference length l_e = |theta_v(Q)| and reference strains (§5.3).
        real(rk), allocatable :: element_length(:), eps_ref(:, :)
        !> Linearized buckling (stress_only): per element the stresses (n, m) held fixed in
        !> place of the elastic ones; not allocated otherwise.
        real(rk), allocatable :: held_stress(:, :)
        !> Reference arc length of the nodes.
        real(rk), allocatable :: node_s(:)
        type(se3_load_t), allocatable :: loads(:)
        !> Driven ends (rs_formulations_end_drive; frame: A0 of the K basis).
        type(end_drive_t), allocatable :: drives(:)
        !> The driven nodes' coordinates at the end of the current step.
        real(rk), allocatable :: q_driven(:, :)
        !> unknown_of(i, k): index of q(i) of node k in Y (0: fixed by a support).
        integer, allocatable :: unknown_of(:, :)
        !> Supports released at a time (&bc release_time): the release time of q(i) of node k
        !> (unset_real: not released), and the held rows of those unknowns.
        real(rk), allocatable :: release_time(:, :)
        !> keep_chart(k): node k's twist is held (one component psi_i fixed, twist_coordinate):
        !> `update` never takes the complement of its rotation vector, which would change
        !> psi_i, and its rotation rows are T(psi)^T times the body rows K dphi, the virtual
        !> work on d psi, of which those of the free components are kept: the equations of
        !> the holonomic constraint psi_i = const, whose reaction is a moment conjugate to psi_i
        !> (semi-tangential, docs/theory/modes.md). Eliminating the body row K dphi_i instead
        !> would make the reaction follow the section's axis (a follower moment, not
        !> conservative) once the end tilts.
        logical, allocatable :: keep_chart(:)
        type(held_rows_t) :: held
        integer :: n_y = 0
        type(csr_pattern_t) :: pattern
        !> CSR position of entry (i, j) of element e's 12 x 12 block (0: fixed row or column).
        integer, allocatable :: element_map(:, :, :)
        real(rk), allocatable :: initial(:)
        ! Workspace (no allocation in the time loop).
        real(rk), allocatable :: q_1(:, :), f_ext(:, :), k_ext(:, :, :)
    contains
        procedure :: init => se3_init
        procedure :: n_state => se3_n_state
        procedure :: n_unknown => se3_n_unknown
        procedure :: jacobian_pattern => se3_jacobian_pattern
        procedure :: initial_state => se3_initial_state
        procedure :: predictor => se3_predictor
        procedure :: update => se3_update
        procedure :: step_residual => se3_step_residual
        procedure :: step_jacobian => se3_step_jacobian
        procedure :: accept_step => se3_accept_step
        procedure :: init_history => se3_init_history
        procedure :: record => se3_record
        procedure :: describe => se3_describe
        procedure :: traits => se3_traits
        procedure :: nodes => se3_nodes
        procedure :: error_entries => se3_error_entries
        procedure :: new_tie => se3_new_tie
        procedure :: set_step_problem => se3_set_step_problem
        procedure :: state_measures => se3_state_measures
        procedure :: path_weights => se3_path_weights
        procedure :: stress_only => se3_stress_only
        procedure, private :: full_q, nodal_loads, energies, stage_velocity, set_drives, &
            rate_of, stage_q, initial_rates, stage_strain_rate, strain_rate_at, drag_matrix
    end type se3_pg_t

    !> The elastic stiffness of an element whose stress is held (stress_only).
    real(rk), parameter :: no_stiffness(6) = 0.0_rk

contains

    ! ---- Building the rod ---------------------------------------------------------------------

    subroutine se3_init(this, scene, rods, err)
        class(se3_pg_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:)
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: message
        real(rk), allocatable :: properties(:, :)
        integer :: e
        if (size(rods) /= 1) then
            RS_SET_ERROR(err, 'se3_pg%init', 'se3_pg rods cannot be joined yet')
            return
        end if
        associate (rod => scene%rods(rods(1)))
            this%name = trim(rod%name)
            this%n_elements = rod%n_elements
            this%n_nodes = rod%n_elements + 1
            this%length = rod%length
            this%quasistatic = scene%time%quasistatic
            this%statics = this%quasistatic
            this%scheme = midpoint_scheme()
            if (.not. this%statics .and. trim(scene%time%scheme) == 'generalized_alpha') &
                this%scheme = generalized_alpha(scene%time%rho_inf)
            properties = element_properties(scene, rod, this%n_elements)
            this%stiffness = properties([1, 2, 3, 6, 4, 5], :)
            this%rho_a = properties(7, :)
            this%inertia = reshape([(properties(8, e) + properties(9, e), properties(8:9, e), &
                e = 1, this%n_elements)], [3, this%n_elements])
            allocate(this%viscosity(6, this%n_elements), source=0.0_rk)
            ! &rod kelvin_voigt_time is in the order (EA, GA1, GA2, EI1, EI2, GJ); the input
            ! check refuses damping in statics.
            if (.not. this%statics) then
                this%viscosity = this%stiffness * spread(rod%kelvin_voigt_time([kv_axial, &
                    kv_shear1, kv_shear2, kv_torsion, kv_bend1, kv_bend2]), 2, this%n_elements)
                this%drag = rod%drag
                this%angular_drag = rod%angular_drag
            end if
            this%kelvin_voigt = any(this%viscosity /= 0.0_rk)
            this%dragged = this%drag /= 0.0_rk .or. this%angular_drag /= 0.0_rk
            call reference_configuration(this, rod)
            call fix_supports(this, scene, err)
            RS_RETURN_IF_ERROR(err)
            call read_loads(this, scene, err)
            RS_RETURN_IF_ERROR(err)
            if (any(this%element_length <= 0.0_rk)) then
                message = 'rod ''' // this%name // ''': an element has zero reference length'
                RS_SET_ERROR(err, 'se3_pg%init', message)
                return
            end if
        end associate
        call build_pattern(this)
        allocate(this%q_1(6, this%n_nodes), this%f_ext(6, this%n_nodes), &
            this%k_ext(6, 6, this%n_nodes))
        if (this%scheme%history) call this%initial_rates()
    end subroutine se3_init

    !> The history y'_0 of generalized-alpha, consistent with the equations of motion at the
    !> initial state (its first step then has the scheme's order): q'_0 = B(q_0) u_0 = (v, T^{-1}
    !> (psi) omega) per node, and u'_0 from M u'_0 = f_ext(q_0, 0) - g_int(q_0) - f_gyr(u_0) on
    !> the free rows, solved with the constant mass matrix (se3_mass_solve). A support's rows
    !> have u' = 0: a clamp and a pin do not accelerate; a driven end's acceleration at t = 0 is
    !> taken as zero too (exact for every time function but a pulse that starts at t = 0, which
    !> the time functions' values alone do not give; docs/theory/se3_pg.md). With damping, f
    !> includes the drag of u_0 and the Kelvin-Voigt stress of the strain rates eps'_0 = (d theta
    !> / d q) q'_0 / l per element, which start the strains' history.
    subroutine initial_rates(this)
        class(se3_pg_t), intent(inout) :: this
        real(rk) :: q(6, this%n_nodes), u(6, this%n_nodes), rows(6, this%n_nodes), g(12)
        real(rk) :: kg(12, 12), accel(6, this%n_nodes), u_e(12), q_e(12), rate(6, this%n_nodes)
        real(rk) :: theta(6), dtheta(6, 12), eps_rate(6), c(12, 12)
        integer :: k, e, n, at
        n = this%n_nodes
        q = reshape(this%initial(1:6 * n), [6, n])
        u = reshape(this%initial(6 * n + 1:12 * n), [6, n])
        do k = 1, n
            rate(1:3, k) = u(1:3, k)
            rate(4:6, k) = matmul(tinv(q(4:6, k)), u(4:6, k))
        end do
        rows = 0.0_rk
        do e = 1, this%n_elements
            q_e = [q(:, e), q(:, e + 1)]
            u_e = [u(:, e), u(:, e + 1)]
            eps_rate = 0.0_rk
            if (this%kelvin_voigt) then
                call se3_twist_tangent(q_e, theta, dtheta)
                eps_rate = matmul(dtheta, [rate(:, e), rate(:, e + 1)]) / this%element_length(e)
                at = this%strain_rate_at(e)
                this%initial(at + 1:at + 6) = eps_rate
            end if
            call se3_viscous_internal_force(this%element_length(e), this%stiffness(:, e), &
                this%eps_ref(:, e), this%viscosity(:, e) * eps_rate, q_e, g)
            rows(:, e:e + 1) = rows(:, e:e + 1) - reshape(g, [6, 2])
            call se3_gyroscopic(this%element_length(e), this%inertia(:, e), u_e, g, kg)
            rows(:, e:e + 1) = rows(:, e:e + 1) - reshape(g, [6, 2])
            if (this%dragged) then
                call this%drag_matrix(e, c)
                rows(:, e:e + 1) = rows(:, e:e + 1) - reshape(matmul(c, u_e), [6, 2])
            end if
        end do
        call this%nodal_loads(0.0_rk, q, .false.)
        rows = rows + this%f_ext
        ! A released support is held at t = 0 (end_is_held): it does not accelerate.
        call se3_mass_solve(this%element_length, this%rho_a, this%inertia, this%unknown_of > 0 &
            .and. this%release_time == unset_real, rows, accel)
        this%initial(12 * n + 1:18 * n) = reshape(rate, [6 * n])
        this%initial(18 * n + 1:24 * n) = reshape(accel, [6 * n])
    end subroutine initial_rates

    !> Nodal reference poses from the centreline and its frame (rs_model_rod_geometry), the
    !> elements' reference lengths l_e = |theta_v(Q)| and strains theta(Q) / l_e (methods §5.3:
    !> exact for any reference the SE(3) interpolation represents, e.g. a straight rod, a circle
    !> or a helix with its frame); the initial rigid velocity field. A prestrained rod (&rod
    !> prestrain) has the translational reference strains divided by 1 + prestrain: those of
    !> its stress-free shape, the given one shortened with the same frames, per unit given
    !> length (docs/theory/prestretched_starts.md; the rotational ones stay).
    subroutine reference_configuration(this, rod)
        type(se3_pg_t), intent(inout) :: this
        type(rod_input_t), intent(in) :: rod
        type(rod_geometry_t) :: geometry
        real(rk) :: d(3, 3), a(3, 3, this%n_nodes), r(3, this%n_nodes), a_rel(3, 3), r_rel(3)
        real(rk) :: theta(6), v(3), omega(3)
        integer :: k, e, at
        geometry = rod_geometry_of(rod)
        allocate(this%node_s(this%n_nodes), this%element_length(this%n_elements), &
            this%eps_ref(6, this%n_elements))
        this%node_s = [(rod%length * real(k - 1, rk) / real(this%n_elements, rk), k = 1, &
            this%n_nodes)]
        allocate(this%initial(this%n_state()), source=0.0_rk)
        do k = 1, this%n_nodes
            d = centreline_frame(geometry, this%node_s(k))
            r(:, k) = centreline_point(geometry, this%node_s(k))
            ! K basis (e_x, e_y, e_z) = (d3, d1, d2).
            a(:, 1, k) = d(:, 3)
            a(:, 2, k) = d(:, 1)
            a(:, 3, k) = d(:, 2)
            at = 6 * (k - 1)
            this%initial(at + 1:at + 3) = r(:, k)
            this%initial(at + 4:at + 6) = log_so3(a(:, :, k))
            ! v = velocity + omega x (r - c), K omega = A^T omega.
            omega = rod%angular_velocity
            v = rod%velocity + matmul(hat(omega), r(:, k) - rod%rotation_center)
            at = 6 * this%n_nodes + 6 * (k - 1)
            if (.not. this%statics) then
                this%initial(at + 1:at + 3) = v
                this%initial(at + 4:at + 6) = matmul(transpose(a(:, :, k)), omega)
            end if
        end do
        do e = 1, this%n_elements
            call pose_relative(a(:, :, e), r(:, e), a(:, :, e + 1), r(:, e + 1), a_rel, r_rel)
            theta = log_se3(a_rel, r_rel)
            this%element_length(e) = norm2(theta(1:3))
            if (this%element_length(e) > 0.0_rk) this%eps_ref(:, e) = theta / this%element_length(e)
            this%eps_ref(1:3, e) = axial_reference(rod) * this%eps_ref(1:3, e)
        end do
    end subroutine reference_configuration

    !> Supports fix the coordinates they hold (rs_model_support): clamped and driven ends r and
    !> psi, pinned ends r, sliding and held ends the held coordinates of r (inertial, methods/
    !> se3_petrov_galerkin.md §5.1, so a slide's axis must be a coordinate axis) and psi with
    !> the rotation, or its twist component alone (twist_coordinate); the rest are the
    !> unknowns, node by node.
    subroutine fix_supports(this, scene, err)
        type(se3_pg_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: message
        logical :: fixed(6, this%n_nodes), held(6), ok
        integer :: i, k, node, axis
        type(end_drive_t) :: drive
        type(end_hold_t) :: hold
        fixed = .false.
        allocate(this%release_time(6, this%n_nodes), source=unset_real)
        allocate(this%keep_chart(this%n_nodes), source=.false.)
        allocate(this%drives(0))
        do i = 1, size(scene%bcs)
            associate (bc => scene%bcs(i))
                if (trim(bc%rod) /= this%name) cycle
                node = merge(1, this%n_nodes, trim(bc%end) == 'start')
                select case (trim(bc%kind))
                case ('clamped', 'pinned', 'sliding', 'held', 'driven', 'free')
                case default
                    message = 'rod ''' // this%name // ''': a ''' // trim(bc%kind) // &
                        ''' end is not available for se3_pg (docs/user/capabilities.md)'
                    RS_SET_ERROR(err, 'se3_pg%init', message)
                    return
                end select
                hold = end_hold(bc)
                ! The twist is no coordinate of held_coordinates: one of psi here.
                call held_coordinates(end_hold_t(hold%position, hold%rotation), held, ok)
                if (ok .and. hold%twist) then
                    axis = twist_coordinate(this%initial(6 * (node - 1) + 4:6 * node))
                    if (axis == 0) then
                        message = twist_refusal(this%name, bc%end, &
                            this%initial(6 * (node - 1) + 4:6 * node))
                        RS_SET_ERROR(err, 'se3_pg%init', message)
                        return
                    end if
                    held(3 + axis) = .true.
                    this%keep_chart(node) = .true.
                end if
                if (bc%release_time == unset_real) then
                    fixed(:, node) = fixed(:, node) .or. held
                else
                    where (held) this%release_time(:, node) = bc%release_time
                end if
                if (.not. ok) then
                    message = coordinate_hold_refusal(this%name, 'se3_pg', 'r', bc)
                    RS_SET_ERROR(err, 'se3_pg%init', message)
                    return
                end if
                if (trim(bc%kind) == 'driven') then
                    call end_drive_init(drive, bc, node, this%initial(6 * (node - 1) + 1:6 * &
                        (node - 1) + 3), exp_so3(this%initial(6 * (node - 1) + 4:6 * node)), err)
                    RS_RETURN_IF_ERROR(err)
                    this%drives = [this%drives, drive]
                end if
            end associate
        end do
        allocate(this%unknown_of(6, this%n_nodes), source=0)
        allocate(this%q_driven(6, this%n_nodes), source=0.0_rk)
        this%n_y = 0
        do k = 1, this%n_nodes
            do i = 1, 6
                if (fixed(i, k)) cycle
                this%n_y = this%n_y + 1
                this%unknown_of(i, k) = this%n_y
            end do
        end do
    end subroutine fix_supports

    !> The component of the rotation vector psi (A = Exp(psi), the end's reference pose) that
    !> is the end's twist, the rotation about its tangent t = A e_x (K basis e_x = d3): at psi
    !> the body rotation is K dphi = T(psi) dpsi (methods/se3_petrov_galerkin.md §5.4) and its
    !> twist e_x . K dphi = (T(psi)^T e_x) . dpsi, so fixing psi_i holds the twist and leaves
    !> the two bending rotations free exactly when T(psi)^T e_x is along e_i (e.g. psi = 0 or
    !> psi along e_x: a rod along x whose frame is turned about x; i = 1). 0 if it is along no
    !> coordinate axis: then no coordinate holds the twist alone.
    pure integer function twist_coordinate(psi) result(axis)
        real(rk), intent(in) :: psi(3)
        real(rk) :: v(3)
        integer :: i, k
        real(rk), parameter :: aligned = 1.0e-12_rk
        v = matmul(transpose(tangent_so3(psi)), [1.0_rk, 0.0_rk, 0.0_rk])
        axis = 0
        do i = 1, 3
            if (norm2(v - [(merge(v(i), 0.0_rk, k == i), k = 1, 3)]) <= aligned * norm2(v)) &
                axis = i
        end do
    end function twist_coordinate

    !> Why the twist of end `end_name` of rod `rod`, whose reference rotation vector is psi, is
    !> no coordinate of se3_pg (twist_coordinate gave 0).
    function twist_refusal(rod, end_name, psi) result(message)
        character(len=*), intent(in) :: rod, end_name
        real(rk), intent(in) :: psi(3)
        character(len=:), allocatable :: message
        message = 'rod ''' // rod // ''': se3_pg holds the twist of the ''' // trim(end_name) // &
            ''' end (hold = ''twist'') by fixing one component of its rotation vector, which ' // &
            'needs T(psi)^T e_x along a coordinate axis; its reference rotation vector psi = (' // &
            vector_text(psi) // ') gives (' // vector_text(matmul(transpose(tangent_so3(psi)), &
            [1.0_rk, 0.0_rk, 0.0_rk])) // ') (a rod along x, its frame turned about x, has it)'
    end function twist_refusal

    !> The driven nodes' coordinates at time t: position and the rotation vector of
    !> Exp(f rotation) A0 nearest to the node's coordinates in x_n (continuous in time).
    subroutine set_drives(this, t, x_n)
        class(se3_pg_t), intent(inout) :: this
        real(rk), intent(in) :: t, x_n(:)
        real(rk) :: frame(3, 3)
        integer :: i, k
        do i = 1, size(this%drives)
            k = this%drives(i)%node
            call this%drives(i)%pose(t, this%q_driven(1:3, k), frame)
            this%q_driven(4:6, k) = nearest_rotation_vector(log_so3(frame), &
                x_n(6 * (k - 1) + 4:6 * k))
        end do
    end subroutine set_drives

    !> End loads (dead: I components; follower: the given vector in the loaded node's director
    !> components (d1, d2, d3), i.e. K components (F3, F1, F2)), distributed loads and gravity.
    subroutine read_loads(this, scene, err)
        type(se3_pg_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        type(error_t), allocatable, intent(out) :: err
        type(se3_load_t) :: load
        integer :: i, n
        allocate(this%loads(size(scene%loads)))
        n = 0
        do i = 1, size(scene%loads)
            associate (input => scene%loads(i))
                if (.not. load_applies_to(input, this%name)) cycle
                load = se3_load_t()
                call time_function_from_load(input, load%factor, err)
                RS_RETURN_IF_ERROR(err)
                load%follower = trim(input%frame) == 'follower'
                select case (trim(input%where))
                case ('start')
                    load%node = 1
                case ('end')
                    load%node = this%n_nodes
                case default
                    load%node = 0
                end select
                if (trim(input%where) == 'gravity') then
                    load%force = input%acceleration
                    load%gravity = .true.
                else if (load%follower) then
                    load%force = [input%force(3), input%force(1), input%force(2)]
                    load%moment = [input%moment(3), input%moment(1), input%moment(2)]
                else
                    load%force = input%force
                    load%moment = input%moment
                end if
                n = n + 1
                this%loads(n) = load
            end associate
        end do
        this%loads = this%loads(1:n)
    end subroutine read_loads

    !> Element couplings: the 12 unknowns of its two nodes.
    subroutine build_pattern(this)
        type(se3_pg_t), intent(inout) :: this
        type(csr_builder_t) :: builder
        integer :: e, i, j, local(12)
        call builder%init(this%n_y, 144 * this%n_elements)
        do e = 1, this%n_elements
            local = [this%unknown_of(:, e), this%unknown_of(:, e + 1)]
            call builder%add_block(local, local)
        end do
        call builder%build(this%pattern)
        ! The held rows of released supports: unknowns of Y and entries of X coincide per node
        ! (6 (k - 1) + i).
        call this%held%init(pack(this%unknown_of, this%release_time /= unset_real), &
            pack(reshape([(i, i = 1, 6 * this%n_nodes)], [6, this%n_nodes]), &
            this%release_time /= unset_real), pack(this%release_time, &
            this%release_time /= unset_real), this%pattern%row_ptr, this%pattern%cols)
        allocate(this%element_map(12, 12, this%n_elements), source=0)
        do e = 1, this%n_elements
            local = [this%unknown_of(:, e), this%unknown_of(:, e + 1)]
            do j = 1, 12
                if (local(j) <= 0) cycle
                do i = 1, 12
                    if (local(i) > 0) this%element_map(i, j, e) = &
                        this%pattern%position(local(i), local(j))
                end do
            end do
        end do
    end subroutine build_pattern

    ! ---- Sizes, state, predictor, update ----------------------------------------------------

    !> The nodes' positions r. Not the rotation vectors psi, which the complement update makes
    !> jump, nor the step-end velocities u, which the midpoint rule leaves with an undamped
    !> (-1)^n component (only u_{n+1/2} is fixed, q_{n+1} = q_n + h B(q_{n+1/2}) u_{n+1/2},
    !> methods/se3_petrov_galerkin.md §7.4; ph_director_error_entries).
    subroutine se3_error_entries(this, weigh)
        class(se3_pg_t), intent(in) :: this
        logical, intent(out) :: weigh(:)
        integer :: k
        weigh = .false.
        do k = 1, this%n_nodes
            weigh(6 * (k - 1) + 1:6 * (k - 1) + 3) = .true.
        end do
    end subroutine se3_error_entries

    !> 12 per node (q, u); 24 with the history (q', u') of generalized-alpha, then with
    !> Kelvin-Voigt damping the history of the strain rates eps' (6 per element, strain_rate_at).
    pure integer function se3_n_state(this)
        class(se3_pg_t), intent(in) :: this
        se3_n_state = merge(24, 12, this%scheme%history) * this%n_nodes
        if (this%scheme%history .and. this%kelvin_voigt) se3_n_state = se3_n_state + &
            6 * this%n_elements
    end function se3_n_state

    !> The offset in the state of element e's strain-rate history eps'_n (generalized-alpha with
    !> Kelvin-Voigt damping only).
    pure integer function strain_rate_at(this, e)
        class(se3_pg_t), intent(in) :: this
        integer, intent(in) :: e
        strain_rate_at = 24 * this%n_nodes + 6 * (e - 1)
    end function strain_rate_at

    !> The strain rate of element e at the stage, on which the Kelvin-Voigt stress acts: the
    !> scheme's stage rate of the objective strains eps = theta / l (methods eq. (38)) from
    !> eps_n (x_n), eps_1 = eps_{n+1} and the history eps'_n; the midpoint rule's is
    !> (eps_{n+1} - eps_n) / h. Only relative poses enter, so a rigid motion has none
    !> (docs/theory/se3_pg.md, "Damping").
    pure function stage_strain_rate(this, h, x_n, e, eps_1) result(rate)
        class(se3_pg_t), intent(in) :: this
        real(rk), intent(in) :: h, x_n(:), eps_1(6)
        integer, intent(in) :: e
        real(rk) :: rate(6)
        real(rk) :: eps_n(6), history(6)
        integer :: at
        call se3_strains(this%element_length(e), x_n(6 * (e - 1) + 1:6 * (e + 1)), eps_n)
        history = 0.0_rk
        if (this%scheme%history) then
            at = this%strain_rate_at(e)
            history = x_n(at + 1:at + 6)
        end if
        rate = this%scheme%stage_rate(h, eps_n, eps_1, history)
    end function stage_strain_rate

    !> Element e's consistent drag matrix (12 x 12, u space): the drag and angular drag per
    !> length on the linearly interpolated velocities (methods eq. (41)) tested with the linear
    !> test functions, l [[1/3, 1/6], [1/6, 1/3]] (x) blockdiag(drag 1_3, angular_drag 1_3):
    !> the consistent mass matrix's form (se3_element_mass) with these coefficients.
    pure subroutine drag_matrix(this, e, c)
        class(se3_pg_t), intent(in) :: this
        integer, intent(in) :: e
        real(rk), intent(out) :: c(12, 12)
        call se3_element_mass(this%element_length(e), this%drag, spread(this%angular_drag, 1, 3), c)
    end subroutine drag_matrix

    pure integer function se3_n_unknown(this)
        class(se3_pg_t), intent(in) :: this
        se3_n_unknown = this%n_y
    end function se3_n_unknown

    subroutine se3_jacobian_pattern(this, row_ptr, cols)
        class(se3_pg_t), intent(in) :: this
        integer, allocatable, intent(out) :: row_ptr(:), cols(:)
        call this%pattern%zero_based(row_ptr, cols)
    end subroutine se3_jacobian_pattern

    subroutine se3_initial_state(this, x)
        class(se3_pg_t), intent(in) :: this
        real(rk), intent(out) :: x(:)
        x = this%initial
    end subroutine se3_initial_state

    !> q_{n+1} as (6, nodes): Y where free, q_n where fixed.
    pure subroutine full_q(this, x_n, y, q)
        class(se3_pg_t), intent(in) :: this
        real(rk), intent(in) :: x_n(:), y(:)
        real(rk), intent(out) :: q(:, :)
        integer :: i, k
        do k = 1, this%n_nodes
            do i = 1, 6
                if (this%unknown_of(i, k) > 0) then
                    q(i, k) = y(this%unknown_of(i, k))
                else if (is_driven(this, k)) then
                    q(i, k) = this%q_driven(i, k)
                else
                    q(i, k) = x_n(6 * (k - 1) + i)
                end if
            end do
        end do
    end subroutine full_q

    pure logical function is_driven(this, k)
        type(se3_pg_t), intent(in) :: this
        integer, intent(in) :: k
        integer :: i
        is_driven = .false.
        do i = 1, size(this%drives)
            if (this%drives(i)%node == k) is_driven = .true.
        end do
    end function is_driven

    !> Statics: the last equilibrium, moved rigidly with the first driven end (its increment
    !> of pose over the step, about its position: exact for a rigid superimposed motion,
    !> methods §10.3, and a linearized-predictor substitute otherwise). Dynamics: q_n + h B(q_n)
    !> u_n (explicit Euler).
    subroutine se3_predictor(this, t_n, h, x_n, y)
        class(se3_pg_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:)
        real(rk), intent(out) :: y(:)
        real(rk) :: q(6), u(6), turn(3, 3), shift(3), pivot(3)
        integer :: i, k, at
        call this%set_drives(step_end_time(this, t_n, h), x_n)
        turn = 0.0_rk
        turn(1, 1) = 1.0_rk
        turn(2, 2) = 1.0_rk
        turn(3, 3) = 1.0_rk
        pivot = 0.0_rk
        shift = 0.0_rk
        if (size(this%drives) > 0 .and. this%statics) then
            k = this%drives(1)%node
            pivot = x_n(6 * (k - 1) + 1:6 * (k - 1) + 3)
            turn = matmul(exp_so3(this%q_driven(4:6, k)), transpose(exp_so3(x_n(6 * (k - 1) + &
                4:6 * k))))
            shift = this%q_driven(1:3, k) - pivot
        end if
        do k = 1, this%n_nodes
            at = 6 * (k - 1)
            q = x_n(at + 1:at + 6)
            if (this%statics .and. size(this%drives) > 0) then
                q(1:3) = pivot + shift + matmul(turn, q(1:3) - pivot)
                q(4:6) = nearest_rotation_vector(log_so3(matmul(turn, exp_so3(q(4:6)))), q(4:6))
            end if
            if (.not. this%statics) then
                u = x_n(6 * this%n_nodes + at + 1:6 * this%n_nodes + at + 6)
                q(1:3) = q(1:3) + h * u(1:3)
                q(4:6) = q(4:6) + h * matmul(tinv(q(4:6)), u(4:6))
            end if
            do i = 1, 6
                if (this%unknown_of(i, k) > 0) y(this%unknown_of(i, k)) = q(i)
            end do
        end do
    end subroutine se3_predictor

    !> X_{n+1}: q from Y; u_{n+1} from the stage velocity, u_n + (u_{n+alpha_f} - u_n) /
    !> alpha_f (the midpoint rule: 2 u_{n+1/2} - u_n; zero in statics); with generalized-alpha
    !> the history of the next step, q'_{n+1} and u'_{n+1} from the update formula (methods
    !> §7.3). Then the complement of every rotation vector longer than complement_angle (pi;
    !> 1.25 pi with generalized-alpha) (methods eq. 40), which changes the coordinates, not the
    !> rotation, so u (K components) stays and psi' is carried to the new chart
    !> (rate_in_complement); not at a node whose twist is held (keep_chart: the complement would
    !> move the held component; its bending rotation then must stay below 2 pi, where T^{-1} is
    !> singular). With Kelvin-Voigt damping, the strains' history eps'_{n+1} by the
    !> same update formula (the strains do not depend on the chart).
    subroutine se3_update(this, t_n, h, x_n, y, x_1)
        class(se3_pg_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: x_1(:)
        real(rk) :: u_stage(6), psi(3), eps_n(6), eps_1(6)
        integer :: k, at, au, aq, aa, n, e
        call this%set_drives(step_end_time(this, t_n, h), x_n)
        call this%full_q(x_n, y, this%q_1)
        n = this%n_nodes
        do k = 1, n
            at = 6 * (k - 1)
            au = 6 * n + at
            aq = 12 * n + at
            aa = 18 * n + at
            if (this%statics) then
                x_1(au + 1:au + 6) = 0.0_rk
            else
                u_stage = this%stage_velocity(h, x_n, k, this%q_1(:, k))
                x_1(au + 1:au + 6) = this%scheme%end_from_stage(x_n(au + 1:au + 6), u_stage)
            end if
            if (this%scheme%history .and. this%statics) then
                ! At rest in a static equilibrium the consistent history is zero: q' = B u = 0,
                ! and M u' = f_ext - g_int - f_gyr = 0 on the free rows.
                x_1(aq + 1:aq + 6) = 0.0_rk
                x_1(aa + 1:aa + 6) = 0.0_rk
            else if (this%scheme%history) then
                x_1(aq + 1:aq + 6) = this%scheme%end_rate(h, x_n(at + 1:at + 6), this%q_1(:, k), &
                    x_n(aq + 1:aq + 6))
                x_1(aa + 1:aa + 6) = this%scheme%end_rate(h, x_n(au + 1:au + 6), &
                    x_1(au + 1:au + 6), x_n(aa + 1:aa + 6))
            end if
            x_1(at + 1:at + 3) = this%q_1(1:3, k)
            psi = this%q_1(4:6, k)
            if (norm2(psi) > complement_angle(this%scheme) .and. .not. this%keep_chart(k)) &
                psi = complement_rotation_vector(psi)
            x_1(at + 4:at + 6) = psi
            if (this%scheme%history .and. any(psi /= this%q_1(4:6, k))) &
                x_1(aq + 4:aq + 6) = rate_in_complement(this%q_1(4:6, k), x_1(aq + 4:aq + 6), &
                (0.5_rk - this%scheme%gamma) * h)
        end do
        if (.not. (this%scheme%history .and. this%kelvin_voigt)) return
        do e = 1, this%n_elements
            at = this%strain_rate_at(e)
            if (this%statics) then
                x_1(at + 1:at + 6) = 0.0_rk
                cycle
            end if
            call se3_strains(this%element_length(e), x_n(6 * (e - 1) + 1:6 * (e + 1)), eps_n)
            call se3_strains(this%element_length(e), [this%q_1(:, e), this%q_1(:, e + 1)], eps_1)
            x_1(at + 1:at + 6) = this%scheme%end_rate(h, eps_n, eps_1, x_n(at + 1:at + 6))
        end do
    end subroutine se3_update

    !> The angle beyond which `update` takes the complement of a rotation vector (methods eq.
    !> 40): pi for the midpoint rule, whose step reads no history, so the chart may change at
    !> every step. Generalized-alpha's history psi' is carried to the new chart only to second
    !> order (rate_in_complement), so every change of chart perturbs the next steps a little;
    !> a node whose rotation angle hovers about pi (the heavy top's during the middle of a
    !> precession: the angle of a half turn about the vertical composed with any spin is pi)
    !> would change chart at nearly every step, and at h = 1e-3 these perturbations excite its
    !> bending-shear modes (max |E - E0| over 5 precessions 0.29 E0 at rho_inf = 0.9, 0.018 E0
    !> with this threshold; docs/theory/se3_pg.md). So its threshold is pi + pi/4: the
    !> complement is then shorter than 3 pi/4, and the chart changes back only after a quarter
    !> turn; |psi| stays far from the singularity of T^{-1} at 2 pi.
    pure real(rk) function complement_angle(scheme)
        type(generalized_alpha_t), intent(in) :: scheme
        complement_angle = merge(1.25_rk * pi, pi, scheme%history)
    end function complement_angle

    !> psi' carried to the complement chart: the derivative of the chart change, D psi_c / D psi
    !> = T^{-1}(psi_c) T(psi) (both charts give the same body rate T psi'), taken at psi_d = psi
    !> + d psi', where d = (1/2 - gamma) h: generalized-alpha's y'_n approximates y' at t_n + d
    !> to second order (its update and stage equations are then exact to O(h^3)), so the map
    !> keeps that order; at psi itself it would leave an O(h) error in the history at every
    !> change of chart (measured on the heavy top at h = 1e-3 with the threshold pi, the charts
    !> changing at nearly every step: max |E - E0| over 5 precessions 0.29 E0 at psi, 0.15 E0 at
    !> psi_d; with complement_angle's threshold 0.0185 and 0.0183 E0).
    pure function rate_in_complement(psi, rate, d) result(rate_c)
        real(rk), intent(in) :: psi(3), rate(3), d
        real(rk) :: rate_c(3)
        real(rk) :: psi_d(3), turns
        psi_d = psi + d * rate
        turns = real(nint(norm2(psi) / (2.0_rk * pi)), rk)
        rate_c = matmul(tinv(psi_d * (1.0_rk - 2.0_rk * pi * turns / norm2(psi_d))), &
            matmul(tangent_so3(psi_d), rate))
    end function rate_in_complement

    !> The history rate of node k in x (which = 1: q', 2: u'); zero without a history (the
    !> midpoint rule reads none).
    pure function rate_of(this, x, k, which) result(rate)
        class(se3_pg_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        integer, intent(in) :: k, which
        real(rk) :: rate(6)
        integer :: at
        rate = 0.0_rk
        if (.not. this%scheme%history) return
        at = 6 * this%n_nodes * (1 + which) + 6 * (k - 1)
        rate = x(at + 1:at + 6)
    end function rate_of

    !> The stage velocity of node k, u_{n+alpha_f} = B(q_{n+alpha_f})^{-1} q'_{n+alpha_m} =
    !> (r'_{n+alpha_m}, T(psi_{n+alpha_f}) psi'_{n+alpha_m}) (methods eq. 39 at the stage),
    !> from q_n and the history in x_n and q_1 = q_{n+1}; the midpoint rule: (dr / h,
    !> T(psi_mid) dpsi / h).
    pure function stage_velocity(this, h, x_n, k, q_1) result(u)
        class(se3_pg_t), intent(in) :: this
        real(rk), intent(in) :: h, x_n(:), q_1(6)
        integer, intent(in) :: k
        real(rk) :: u(6)
        real(rk) :: rate(6)
        associate (q_n => x_n(6 * (k - 1) + 1:6 * k))
            rate = this%scheme%stage_rate(h, q_n, q_1, this%rate_of(x_n, k, 1))
            u(1:3) = rate(1:3)
            u(4:6) = matmul(tangent_so3(this%scheme%stage_value(q_n(4:6), q_1(4:6))), rate(4:6))
        end associate
    end function stage_velocity

    !> The stage coordinates q_{n+alpha_f} of all nodes (statics: q_{n+1} itself).
    pure subroutine stage_q(this, x_n, q_1, q_at)
        class(se3_pg_t), intent(in) :: this
        real(rk), intent(in) :: x_n(:), q_1(:, :)
        real(rk), intent(out) :: q_at(:, :)
        integer :: k
        if (this%statics) then
            q_at = q_1
            return
        end if
        do k = 1, this%n_nodes
            q_at(:, k) = this%scheme%stage_value(x_n(6 * (k - 1) + 1:6 * k), q_1(:, k))
        end do
    end subroutine stage_q

    !> The time of the step's forces: t_{n+1} in statics (the load time t_static in the
    !> initial equilibrium), else t_n + alpha_f h.
    pure real(rk) function force_time(this, t_n, h)
        type(se3_pg_t), intent(in) :: this
        real(rk), intent(in) :: t_n, h
        force_time = merge(step_end_time(this, t_n, h), t_n + this%scheme%alpha_f * h, &
            this%statics)
    end function force_time

    !> The time that decides whether a released support still holds (held_rows_t): the step's
    !> start t_n, or the load time t_static of the initial equilibrium.
    pure real(rk) function held_time(this, t_n)
        type(se3_pg_t), intent(in) :: this
        real(rk), intent(in) :: t_n
        held_time = merge(this%t_static, t_n, this%static_stage)
    end function held_time

    !> The time at the step's end, t_n + h, where drives are evaluated; the load time t_static
    !> in the initial equilibrium, whose t_n and h are the continuation's pseudo-time.
    pure real(rk) function step_end_time(this, t_n, h)
        type(se3_pg_t), intent(in) :: this
        real(rk), intent(in) :: t_n, h
        step_end_time = merge(this%t_static, t_n + h, this%static_stage)
    end function step_end_time

    ! ---- The step problem -------------------------------------------------------------------

    !> F(Y) in the virtual-displacement rows (I dr_i, K_i dphi_i) of the free unknowns:
    !> statics g_int(q) - f_ext(q, t_{n+1}); dynamics, at the stage (methods eqs. 42-45,
    !> 49-51, §7.3), M u'_{n+alpha_m} + g_int(q_{n+alpha_f}) + f_gyr(u_{n+alpha_f}) -
    !> f_ext(q_{n+alpha_f}, t_n + alpha_f h), with u_{n+1} = u_n + (u_{n+alpha_f} - u_n) /
    !> alpha_f and u'_{n+alpha_m} from u_n, u_{n+1} and u'_n; the midpoint rule: M (u_{n+1} -
    !> u_n) / h + g_int(q_mid) + f_gyr(u_mid) - f_ext(q_mid, t_{n+1/2}). Damping (docs/theory/
    !> se3_pg.md, "Damping"): g_int with the Kelvin-Voigt stress V eps'_s of the stage strain
    !> rate (stage_strain_rate) added to the elastic one, and the drag C u_{n+alpha_f}.
    subroutine se3_step_residual(this, t_n, h, x_n, y, f, status)
        class(se3_pg_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: f(:)
        integer, intent(out) :: status
        real(rk) :: q_at(6, this%n_nodes), rows(6, this%n_nodes)
        integer :: k, i
        call this%set_drives(step_end_time(this, t_n, h), x_n)
        call this%full_q(x_n, y, this%q_1)
        call this%stage_q(x_n, this%q_1, q_at)
        call body_rows(this, t_n, h, x_n, q_at, rows)
        do k = 1, this%n_nodes
            if (this%keep_chart(k)) rows(4:6, k) = matmul(transpose(tangent_so3(q_at(4:6, k))), &
                rows(4:6, k))
            do i = 1, 6
                if (this%unknown_of(i, k) > 0) f(this%unknown_of(i, k)) = rows(i, k)
            end do
        end do
        ! The Newton homotopy of the continuation: t_n + h is the pseudo-time tau.
        if (this%continuing) f = f - max(0.0_rk, 1.0_rk - (t_n + h)) * this%anchor
        call this%held%apply_residual(held_time(this, t_n), h, this%static_stage, x_n, y, f)
        status = state_valid
        if (any(f /= f)) status = state_invalid
    end subroutine se3_step_residual

    !> The step's generalized forces per node in the virtual-displacement rows (I dr, K dphi)
    !> of every coordinate, held ones included (se3_step_residual), at the stage q_at, with
    !> this%q_1 = q_{n+1}.
    subroutine body_rows(this, t_n, h, x_n, q_at, rows)
        type(se3_pg_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), q_at(:, :)
        real(rk), intent(out) :: rows(:, :)
        real(rk) :: q_e(12), g(12), m(12, 12), u_stage(12), accel(12), gyr(12), kg(12, 12)
        real(rk) :: c(12, 12), eps_1(6)
        integer :: e
        rows = 0.0_rk
        do e = 1, this%n_elements
            q_e = [q_at(:, e), q_at(:, e + 1)]
            if (allocated(this%held_stress)) then
                call se3_viscous_internal_force(this%element_length(e), no_stiffness, &
                    this%eps_ref(:, e), this%held_stress(:, e), q_e, g)
            else if (this%kelvin_voigt .and. .not. this%statics) then
                call se3_strains(this%element_length(e), [this%q_1(:, e), this%q_1(:, e + 1)], &
                    eps_1)
                call se3_viscous_internal_force(this%element_length(e), this%stiffness(:, e), &
                    this%eps_ref(:, e), &
                    this%viscosity(:, e) * this%stage_strain_rate(h, x_n, e, eps_1), &
                    q_e, g)
            else
                call se3_internal_force(this%element_length(e), this%stiffness(:, e), &
                    this%eps_ref(:, e), q_e, g)
            end if
            if (.not. this%statics) then
                call stage_motion(this, h, x_n, e, u_stage, accel)
                call se3_element_mass(this%element_length(e), this%rho_a(e), this%inertia(:, e), m)
                call se3_gyroscopic(this%element_length(e), this%inertia(:, e), u_stage, gyr, kg)
                g = g + matmul(m, accel) + gyr
                if (this%dragged) then
                    call this%drag_matrix(e, c)
                    g = g + matmul(c, u_stage)
                end if
            end if
            rows(:, e) = rows(:, e) + g(1:6)
            rows(:, e + 1) = rows(:, e + 1) + g(7:12)
        end do
        call this%nodal_loads(force_time(this, t_n, h), q_at, .false.)
        rows = rows - this%f_ext
    end subroutine body_rows

    !> The stage velocities u_{n+alpha_f} and accelerations u'_{n+alpha_m} of element e's two
    !> nodes (12 each), from x_n and q_{n+1} (this%q_1).
    pure subroutine stage_motion(this, h, x_n, e, u_stage, accel)
        type(se3_pg_t), intent(in) :: this
        real(rk), intent(in) :: h, x_n(:)
        integer, intent(in) :: e
        real(rk), intent(out) :: u_stage(12), accel(12)
        integer :: node, k, au
        do node = 0, 1
            k = e + node
            au = 6 * this%n_nodes + 6 * (k - 1)
            associate (u_n => x_n(au + 1:au + 6), u_s => u_stage(6 * node + 1:6 * node + 6))
                u_s = this%stage_velocity(h, x_n, k, this%q_1(:, k))
                accel(6 * node + 1:6 * node + 6) = this%scheme%stage_rate(h, u_n, &
                    this%scheme%end_from_stage(u_n, u_s), this%rate_of(x_n, k, 2))
            end associate
        end do
    end subroutine stage_motion

    !> dF/dY: the element tangents of methods §6.4 (analytic, checked against finite differences
    !> in tests/unit/formulations/test_se3_pg_element), the follower and dead load tangents,
    !> and in dynamics the chain through q_{n+alpha_f} (factor alpha_f) and the stage velocity
    !> (stage_velocity_jacobian), with d u'_{n+alpha_m} / d u_{n+alpha_f} = alpha_m / (h gamma
    !> alpha_f) (the midpoint rule: 2 / h); checked against central differences in
    !> tests/unit/formulations/test_se3_pg.
    subroutine se3_step_jacobian(this, t_n, h, x_n, y, values, status)
        class(se3_pg_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: values(:)
        integer, intent(out) :: status
        real(rk) :: q_e(12), k(12, 12), m(12, 12), kg(12, 12), gyr(12), u_stage(12), du(12, 12)
        real(rk) :: du_node(6, 6), accel(12), g(12), b_t(12, 6), theta(6), dtheta(6, 12), c(12, 12)
        real(rk) :: q_at(6, this%n_nodes), scale
        integer :: e, i, j, node
        call this%set_drives(step_end_time(this, t_n, h), x_n)
        call this%full_q(x_n, y, this%q_1)
        call this%stage_q(x_n, this%q_1, q_at)
        scale = merge(1.0_rk, this%scheme%alpha_f, this%statics)
        call this%nodal_loads(force_time(this, t_n, h), q_at, .true.)
        values = 0.0_rk
        do e = 1, this%n_elements
            q_e = [q_at(:, e), q_at(:, e + 1)]
            if (allocated(this%held_stress)) then
                call se3_viscous_internal_force(this%element_length(e), no_stiffness, &
                    this%eps_ref(:, e), this%held_stress(:, e), q_e, g, k)
            else if (this%kelvin_voigt .and. .not. this%statics) then
                call se3_twist_tangent([this%q_1(:, e), this%q_1(:, e + 1)], theta, dtheta)
                call se3_viscous_internal_force(this%element_length(e), this%stiffness(:, e), &
                    this%eps_ref(:, e), this%viscosity(:, e) * this%stage_strain_rate(h, x_n, e, &
                    theta / this%element_length(e)), q_e, g, k, b_t)
            else
                call se3_internal_tangent(this%element_length(e), this%stiffness(:, e), &
                    this%eps_ref(:, e), q_e, k)
            end if
            k = scale * k
            ! Load tangents enter once per node: with the element that starts there, and the
            ! last node with the last element.
            do node = 0, 1
                if (node == 1 .and. e < this%n_elements) cycle
                k(6 * node + 1:6 * node + 6, 6 * node + 1:6 * node + 6) = &
                    k(6 * node + 1:6 * node + 6, 6 * node + 1:6 * node + 6) - &
                    scale * this%k_ext(:, :, e + node)
            end do
            if (.not. this%statics) then
                du = 0.0_rk
                do node = 0, 1
                    call stage_velocity_jacobian(this%scheme, h, &
                        x_n(6 * (e + node - 1) + 1:6 * (e + node)), this%q_1(:, e + node), &
                        this%rate_of(x_n, e + node, 1), du_node)
                    du(6 * node + 1:6 * node + 6, 6 * node + 1:6 * node + 6) = du_node
                end do
                call stage_motion(this, h, x_n, e, u_stage, accel)
                call se3_element_mass(this%element_length(e), this%rho_a(e), this%inertia(:, e), m)
                call se3_gyroscopic(this%element_length(e), this%inertia(:, e), u_stage, gyr, kg)
                k = k + matmul(this%scheme%stage_rate_factor(h) / this%scheme%alpha_f * m + kg, du)
                if (this%dragged) then
                    call this%drag_matrix(e, c)
                    k = k + matmul(c, du)
                end if
                ! The Kelvin-Voigt stress V eps'_s: d eps'_s / d q_{n+1} = alpha_m / (h gamma)
                ! d theta(q_{n+1}) / d q / l (the midpoint rule: 1 / h).
                if (this%kelvin_voigt) then
                    do j = 1, 12
                        dtheta(:, j) = this%viscosity(:, e) * this%scheme%stage_rate_factor(h) / &
                            this%element_length(e) * dtheta(:, j)
                    end do
                    k = k + matmul(b_t, dtheta)
                end if
            end if
            ! A held twist's rows are T^T times the body rows (se3_step_residual).
            do node = 0, 1
                if (.not. this%keep_chart(e + node)) cycle
                k(6 * node + 4:6 * node + 6, :) = matmul(transpose(tangent_so3(q_at(4:6, &
                    e + node))), k(6 * node + 4:6 * node + 6, :))
            end do
            do j = 1, 12
                do i = 1, 12
                    if (this%element_map(i, j, e) > 0) values(this%element_map(i, j, e)) = &
                        values(this%element_map(i, j, e)) + k(i, j)
                end do
            end do
        end do
        if (any(this%keep_chart)) call twist_row_tangent(this, t_n, h, x_n, q_at, scale, values)
        call this%held%apply_jacobian(held_time(this, t_n), h, this%static_stage, values)
        status = state_valid
        if (any(values /= values)) status = state_invalid
    end subroutine se3_step_jacobian

    !> The rest of the derivative of a held twist's rows T(psi)^T r (se3_step_residual): the
    !> derivative of T^T at the stage rotation psi_s times the node's body rows r, sum_j
    !> (dT/dpsi_j)^T r d psi_s,j / d psi_j, with d psi_s / d psi_{n+1} = `scale`, on the node's
    !> free rotation coordinates.
    subroutine twist_row_tangent(this, t_n, h, x_n, q_at, scale, values)
        type(se3_pg_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), q_at(:, :), scale
        real(rk), intent(inout) :: values(:)
        real(rk) :: rows(6, this%n_nodes), dt(3, 3, 3), column(3)
        integer :: k, i, j, row, col
        call body_rows(this, t_n, h, x_n, q_at, rows)
        do k = 1, this%n_nodes
            if (.not. this%keep_chart(k)) cycle
            dt = tangent_so3_derivative(q_at(4:6, k))
            do j = 1, 3
                col = this%unknown_of(3 + j, k)
                if (col <= 0) cycle
                column = scale * matmul(transpose(dt(:, :, j)), rows(4:6, k))
                do i = 1, 3
                    row = this%unknown_of(3 + i, k)
                    if (row <= 0) cycle
                    values(this%pattern%position(row, col)) = &
                        values(this%pattern%position(row, col)) + column(i)
                end do
            end do
        end do
    end subroutine twist_row_tangent

    !> d u_{n+alpha_f} / d q_{n+1} of one node (6 x 6) for `stage_velocity`: c = alpha_m / (h
    !> gamma) on the positions, and c T(psi_s) + alpha_f sum_k dT/dpsi_k(psi_s) psi'_s e_k^T on
    !> the rotation, psi_s = psi_{n+alpha_f}, psi'_s = psi'_{n+alpha_m} (the midpoint rule:
    !> (T(psi_mid) + 1/2 sum_k dT/dpsi_k dpsi e_k^T) / h).
    pure subroutine stage_velocity_jacobian(scheme, h, q_n, q_1, rate_n, du)
        type(generalized_alpha_t), intent(in) :: scheme
        real(rk), intent(in) :: h, q_n(6), q_1(6), rate_n(6)
        real(rk), intent(out) :: du(6, 6)
        real(rk) :: dt(3, 3, 3), rate(6), psi_s(3), c
        integer :: j
        c = scheme%stage_rate_factor(h)
        rate = scheme%stage_rate(h, q_n, q_1, rate_n)
        psi_s = scheme%stage_value(q_n(4:6), q_1(4:6))
        du = 0.0_rk
        do j = 1, 3
            du(j, j) = c
        end do
        dt = tangent_so3_derivative(psi_s)
        du(4:6, 4:6) = c * tangent_so3(psi_s)
        do j = 1, 3
            du(4:6, 3 + j) = du(4:6, 3 + j) + scheme%alpha_f * matmul(dt(:, :, j), rate(4:6))
        end do
    end subroutine stage_velocity_jacobian

    !> The loads at time t on the nodes at poses q (f_ext, rows I dr and K dphi) and, if
    !> `tangent`, their derivatives d f_ext / d q per node (k_ext): follower forces A(psi) b_K,
    !> dead moments A(psi)^T c_I. Distributed loads: consistent l_e / 2 per node for the force;
    !> the moment lumped at the nodes as A_i^T c l_e / 2 (docs/theory/se3_pg.md).
    subroutine nodal_loads(this, t, q, tangent)
        class(se3_pg_t), intent(inout) :: this
        real(rk), intent(in) :: t, q(:, :)
        logical, intent(in) :: tangent
        real(rk) :: factor, f(3), k(3, 3), weight
        integer :: i, e, node, n
        this%f_ext = 0.0_rk
        if (tangent) this%k_ext = 0.0_rk
        do i = 1, size(this%loads)
            associate (load => this%loads(i))
                factor = load%factor%value(t)
                if (factor == 0.0_rk) cycle
                do e = 0, merge(0, this%n_elements, load%node > 0)
                    do node = 0, 1
                        if (load%node > 0) then
                            if (node == 1) cycle
                            n = load%node
                            weight = factor
                        else
                            if (e == 0) cycle
                            n = e + node
                            weight = factor * 0.5_rk * this%element_length(e)
                            if (load%gravity) weight = weight * this%rho_a(e)
                        end if
                        if (load%follower) then
                            call follower_force(q(4:6, n), weight * load%force, f, k)
                            this%f_ext(1:3, n) = this%f_ext(1:3, n) + f
                            if (tangent) this%k_ext(1:3, 4:6, n) = this%k_ext(1:3, 4:6, n) + k
                            this%f_ext(4:6, n) = this%f_ext(4:6, n) + weight * load%moment
                        else
                            this%f_ext(1:3, n) = this%f_ext(1:3, n) + weight * load%force
                            call dead_moment(q(4:6, n), weight * load%moment, f, k)
                            this%f_ext(4:6, n) = this%f_ext(4:6, n) + f
                            if (tangent) this%k_ext(4:6, 4:6, n) = this%k_ext(4:6, 4:6, n) + k
                        end if
                    end do
                end do
            end associate
        end do
    end subroutine nodal_loads

    ! ---- After a step -------------------------------------------------------------------------

    !> The energy terms of the step (terms(1)): the work of the loads over the step,
    !> f_ext(q_s, t_s) . (dr, T(psi_s) dpsi) per node at the stage (q_{n+alpha_f}, t_n +
    !> alpha_f h; the midpoint rule's midpoint; statics: at t_{n+1} and q_{n+1}), and H_n,
    !> H_{n+1}, and the damping's dissipation D_n, whose balance H_{n+1} - H_n - W + D the
    !> record ledger sums. Neither scheme makes it vanish for this element (methods §7.4); it
    !> measures the scheme's energy error, and generalized-alpha's numerical dissipation.
    subroutine se3_accept_step(this, t_n, h, x_n, x_1, terms)
        class(se3_pg_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), x_1(:)
        type(step_energy_t), intent(out) :: terms(:)
        real(rk) :: q_n(6, this%n_nodes), q_1(6, this%n_nodes), q_at(6, this%n_nodes)
        real(rk) :: ds(6, this%n_nodes), ds_e(12), c(12, 12), eps_n(6), eps_1(6)
        real(rk) :: work, kinetic_n, strain_n, kinetic_1, strain_1, dissipated
        integer :: k, e
        if (this%static_stage) then
            ! The initial equilibrium is not a time step: no energy terms, no grid step.
            terms(1) = step_energy_t(reported=.false., grid_step=.false.)
            return
        end if
        q_n = reshape(x_n(1:6 * this%n_nodes), [6, this%n_nodes])
        q_1 = reshape(x_1(1:6 * this%n_nodes), [6, this%n_nodes])
        ! x_1 holds complemented rotation vectors: undo on the nodes whose angle jumped, so that
        ! the increment is the one Newton took.
        do k = 1, this%n_nodes
            q_1(4:6, k) = nearest_rotation_vector(q_1(4:6, k), q_n(4:6, k))
        end do
        call this%stage_q(x_n, q_1, q_at)
        call this%nodal_loads(force_time(this, t_n, h), q_at, .false.)
        work = 0.0_rk
        do k = 1, this%n_nodes
            ds(1:3, k) = q_1(1:3, k) - q_n(1:3, k)
            ds(4:6, k) = matmul(tangent_so3(q_at(4:6, k)), q_1(4:6, k) - q_n(4:6, k))
            work = work + dot_product(this%f_ext(:, k), ds(:, k))
        end do
        ! The damping's D_n >= 0 (docs/theory/se3_pg.md, "Damping"): h l (d eps / h)^T V (d eps /
        ! h) per element and h (ds / h)^T C (ds / h) with the drag matrix C (for the midpoint
        ! rule the drag's work itself).
        dissipated = 0.0_rk
        do e = 1, this%n_elements
            if (this%kelvin_voigt .and. .not. this%statics) then
                call se3_strains(this%element_length(e), q_n(:, e:e + 1), eps_n)
                call se3_strains(this%element_length(e), q_1(:, e:e + 1), eps_1)
                dissipated = dissipated + this%element_length(e) / h * &
                    dot_product(eps_1 - eps_n, this%viscosity(:, e) * (eps_1 - eps_n))
            end if
            if (this%dragged) then
                call this%drag_matrix(e, c)
                ds_e = [ds(:, e), ds(:, e + 1)]
                dissipated = dissipated + dot_product(ds_e, matmul(c, ds_e)) / h
            end if
        end do
        call this%energies(x_n, kinetic_n, strain_n)
        call this%energies(x_1, kinetic_1, strain_1)
        terms(1) = step_energy_t(reported=.true., before=kinetic_n + strain_n, &
            after=kinetic_1 + strain_1, work=work, dissipated=dissipated)
    end subroutine se3_accept_step

    !> Kinetic energy 1/2 u^T M u (consistent mass) and strain energy sum_e l_e W(eps_e).
    subroutine energies(this, x, kinetic, strain)
        class(se3_pg_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        real(rk), intent(out) :: kinetic, strain
        real(rk) :: m(12, 12), u(12), q(12)
        integer :: e, au
        kinetic = 0.0_rk
        strain = 0.0_rk
        do e = 1, this%n_elements
            q = x(6 * (e - 1) + 1:6 * (e + 1))
            strain = strain + se3_strain_energy(this%element_length(e), this%stiffness(:, e), &
                this%eps_ref(:, e), q)
            if (this%statics) cycle
            au = 6 * this%n_nodes + 6 * (e - 1)
            u = x(au + 1:au + 12)
            call se3_element_mass(this%element_length(e), this%rho_a(e), this%inertia(:, e), m)
            kinetic = kinetic + 0.5_rk * dot_product(u, matmul(m, u))
        end do
    end subroutine energies

    ! ---- Output (DESIGN.md §7) ---------------------------------------------------------------

    subroutine se3_init_history(this, histories, capacity)
        class(se3_pg_t), intent(in) :: this
        type(rod_history_t), intent(inout), target :: histories(:)
        integer, intent(in) :: capacity
        integer :: e
        call histories(1)%init(this%name, 'se3_pg', this%n_nodes, this%n_elements, capacity)
        histories(1)%mesh = this%node_s
        histories(1)%stress_mesh = [(0.5_rk * (this%node_s(e) + this%node_s(e + 1)), &
            e = 1, this%n_elements)]
        deallocate(histories(1)%constraint_residual)
    end subroutine se3_init_history

    !> Positions, directors (d1, d2, d3) = (A e_y, A e_z, A e_x), velocities, director rates
    !> A (omega x e), the constant element strains and stresses in director components
    !> (Gamma1, Gamma2, Gamma3) = (gamma_y, gamma_z, gamma_x), likewise K, N and M; energies;
    !> momenta with the consistent mass. The sums since the last record are the ledger's.
    subroutine se3_record(this, histories, t, x)
        class(se3_pg_t), intent(inout) :: this
        type(rod_history_t), intent(inout), target :: histories(:)
        real(rk), intent(in) :: t, x(:)
        real(rk) :: a(3, 3), u(6), eps(6), n(6), kinetic, strain, m(12, 12), p(12), q(12)
        real(rk) :: linear(3), angular(3), centre(3)
        integer :: rec, k, e, at, au, node
        integer, parameter :: director_column(3) = [2, 3, 1]
        rec = histories(1)%next_record()
        if (rec == 0) return
        associate (h => histories(1))
            h%time(rec) = t
            do k = 1, this%n_nodes
                at = 6 * (k - 1)
                au = 6 * this%n_nodes + at
                a = exp_so3(x(at + 4:at + 6))
                u = x(au + 1:au + 6)
                h%position(:, k, rec) = x(at + 1:at + 3)
                h%velocity(:, k, rec) = u(1:3)
                h%directors(:, :, k, rec) = a(:, director_column)
                h%director_velocity(:, :, k, rec) = matmul(a, matmul(hat(u(4:6)), &
                    identity_columns(director_column)))
            end do
            linear = 0.0_rk
            angular = 0.0_rk
            centre = 0.0_rk
            do e = 1, this%n_elements
                q = x(6 * (e - 1) + 1:6 * (e + 1))
                call se3_strains(this%element_length(e), q, eps)
                n(1:3) = this%stiffness(1:3, e) * (eps(1:3) - this%eps_ref(1:3, e))
                n(4:6) = this%stiffness(4:6, e) * (eps(4:6) - this%eps_ref(4:6, e))
                h%strains(:, e, rec) = [eps(2), eps(3), eps(1), eps(5), eps(6), eps(4)]
                h%stress(:, e, rec) = [n(2), n(3), n(1), n(5), n(6), n(4)]
                centre = centre + 0.5_rk * this%element_length(e) * (q(1:3) + q(7:9))
                if (this%statics) cycle
                call se3_element_mass(this%element_length(e), this%rho_a(e), this%inertia(:, e), m)
                p = matmul(m, x(6 * this%n_nodes + 6 * (e - 1) + 1:6 * this%n_nodes + 6 * (e + 1)))
                do node = 0, 1
                    linear = linear + p(6 * node + 1:6 * node + 3)
                    angular = angular + matmul(hat(q(6 * node + 1:6 * node + 3)), &
                        p(6 * node + 1:6 * node + 3)) + matmul(exp_so3(q(6 * node + 4:6 * node + 6)), &
                        p(6 * node + 4:6 * node + 6))
                end do
            end do
            call this%energies(x, kinetic, strain)
            h%kinetic(rec) = kinetic
            h%strain(rec) = strain
            h%total(rec) = kinetic + strain
            h%linear_momentum(:, rec) = linear
            h%angular_momentum(:, rec) = angular
            h%center_of_mass(:, rec) = centre / sum(this%element_length)
        end associate
    end subroutine se3_record

    function se3_describe(this) result(text)
        class(se3_pg_t), intent(in) :: this
        character(len=:), allocatable :: text
        character(len=:), allocatable :: problem
        problem = 'statics'
        if (.not. this%statics) problem = 'dynamics, midpoint rule'
        if (this%scheme%history) problem = 'dynamics, generalized-alpha, rho_inf = ' // &
            str(this%scheme%rho_inf)
        text = 'rod ''' // this%name // ''': se3_pg (' // problem // '), ' // &
            str(this%n_elements) // ' two-node SE(3) elements, ' // &
            str(this%n_y) // ' Newton unknowns, ' // str(this%pattern%nnz()) // &
            ' Jacobian non-zeros'
    end function se3_describe

    !> The traits of se3_pg: plain Newton-Raphson, as the paper (methods §7.2): the stiffness
    !> ratios of slender rods (shear l GA against bending EI / l) make PETSc's backtracking cut
    !> nearly every step. Everything else keeps its default (no endpoint solve, the chain LU),
    !> and the energy: the midpoint rule may create some (methods §7.4, unchecked), while
    !> generalized-alpha is stable and damps, so its sentinel is the dissipative one (energy
    !> created on the scale of all the energy the rod held: a blown-up run).
    pure function se3_traits(this) result(traits)
        class(se3_pg_t), intent(in) :: this
        type(formulation_traits_t) :: traits
        traits%full_newton = .true.
        traits%equilibrium_steps = this%quasistatic
        if (this%scheme%history) traits%energy_scheme = energy_dissipative
        ! The midpoint rule in q alone: u_mid = T(psi_mid) dpsi / h, M (u_{n+1} - u_n) / h = 2 M
        ! (u_mid - u_n) / h and the forces at q_mid (docs/theory/modes.md).
        if (.not. this%statics .and. .not. this%scheme%history) &
            traits%modal_form = modal_second_order
    end function se3_traits

    !> The initial equilibrium of a dynamic run (`endpoint` with continue_from; rod_run): the
    !> next steps are the statics at load time t_load (the step problem of a quasistatic run,
    !> loads and drives at t_load), continued from continue_from: its static residual, for
    !> its own coordinates (the statics predictor's Y), is removed with the weight 1 - tau.
    !> Back (not `endpoint`): the dynamics again. A quasistatic run steps its statics along
    !> the time grid and asks for neither.
    subroutine se3_set_step_problem(this, endpoint, t_load, continue_from)
        class(se3_pg_t), intent(inout) :: this
        logical, intent(in) :: endpoint
        real(rk), intent(in) :: t_load
        real(rk), intent(in), optional :: continue_from(:)
        real(rk) :: y(this%n_y)
        integer :: status
        this%continuing = .false.
        this%static_stage = endpoint .and. .not. this%quasistatic
        this%statics = this%quasistatic .or. this%static_stage
        this%t_static = t_load
        if (.not. (this%static_stage .and. present(continue_from))) return
        call this%predictor(0.0_rk, 1.0_rk, continue_from, y)
        if (allocated(this%anchor)) deallocate(this%anchor)
        allocate(this%anchor(this%n_y))
        call this%step_residual(0.0_rk, 1.0_rk, continue_from, y, this%anchor, status)
        this%continuing = .true.
    end subroutine se3_set_step_problem

    !> No kinetic energy is reported (no &time relaxation for se3_pg); with `from`, the largest
    !> rotation of a node's section from `from` to x, |log(Exp(psi_x) Exp(psi_from)^T)| (a
    !> continuation's increment bound, rod_run).
    function se3_state_measures(this, x, from) result(measures)
        class(se3_pg_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        real(rk), intent(in), optional :: from(:)
        type(state_measures_t) :: measures
        integer :: k, at
        if (.not. present(from)) return
        do k = 1, this%n_nodes
            at = 6 * (k - 1)
            measures%largest_rotation = max(measures%largest_rotation, norm2(log_so3(matmul( &
                exp_so3(x(at + 4:at + 6)), transpose(exp_so3(from(at + 4:at + 6)))))))
        end do
    end function se3_state_measures

    !> The continuation's path weights (rod_formulation_t%path_weights): the free positions by
    !> 1 / L^2 and rotation vectors by 1 (a small turn K dphi = T(psi) dpsi changes psi by
    !> dtheta to first order near psi = 0; methods/se3_petrov_galerkin.md §5.4), each over the
    !> number of nodes.
    subroutine se3_path_weights(this, w)
        class(se3_pg_t), intent(in) :: this
        real(rk), intent(out) :: w(:)
        integer :: i, k
        w = 0.0_rk
        do k = 1, this%n_nodes
            do i = 1, 6
                if (this%unknown_of(i, k) == 0) cycle
                w(this%unknown_of(i, k)) = merge(1.0_rk / this%length**2, 1.0_rk, i <= 3) / &
                    this%n_nodes
            end do
        end do
    end subroutine se3_path_weights

    !> The node table for couplings (rs_formulations_formulation): coordinates q = (r, psi),
    !> rows the virtual-displacement rows (I dr, K dphi) of the free ones, which carry forces
    !> themselves (not times h) and body rotations; held values and reference coordinates from
    !> the reference configuration (driven ends move: held_moves).
    function se3_nodes(this) result(nodes)
        class(se3_pg_t), intent(in) :: this
        type(rod_nodes_t) :: nodes
        integer :: i, k
        nodes%n_coordinates = 6
        nodes%n_nodes = this%n_nodes
        nodes%n_elements = this%n_elements
        nodes%degree = 1
        nodes%n_gauss = 1
        nodes%force_h_power = 0
        nodes%rotation_vector_at = 4
        nodes%held_moves = size(this%drives) > 0
        allocate(nodes%element_length, source=this%element_length)
        allocate(nodes%state(6, this%n_nodes), nodes%unknown(6, this%n_nodes), &
            nodes%momentum(6, this%n_nodes), nodes%held(6, this%n_nodes))
        do k = 1, this%n_nodes
            do i = 1, 6
                nodes%state(i, k) = 6 * (k - 1) + i
            end do
            nodes%held(:, k) = this%initial(6 * (k - 1) + 1:6 * k)
        end do
        nodes%unknown = this%unknown_of
        nodes%momentum = this%unknown_of
    end function se3_nodes

    !> The tie of `kind` in se3_pg's coordinates (rs_se3_pg_tie); none for an unknown kind.
    subroutine se3_new_tie(this, kind, q_a, q_b, axis, tie)
        class(se3_pg_t), intent(in) :: this
        character(len=*), intent(in) :: kind
        real(rk), intent(in) :: q_a(:), q_b(:), axis(3)
        class(node_tie_t), allocatable, intent(out) :: tie
        type(se3_pg_node_tie_t) :: made
        call se3_pg_node_tie(trim(kind), q_a(1:6), q_b(1:6), axis, made)
        if (len_trim(made%kind) == 0 .or. made%n == 0) return
        allocate(tie, source=made)
    end subroutine se3_new_tie

    !> Linearized buckling's stress stiffness (rod_formulation_t%stress_only; docs/theory/
    !> modes.md): with `loaded`, every element's stress is held at the elastic stress of the
    !> loaded state, sigma_1 = C (eps(q_loaded) - eps_ref) (methods eq. (12)), in place of
    !> the elastic one: the internal force is that of sigma_1 (eq. (42)) and its tangent the
    !> terms of the stresses n, m in methods §6.4 alone, the stress (geometric) stiffness of
    !> sigma_1 at any state; the loads keep their tangents. Computed directly, not as the
    !> difference of two tangents that share the elastic stiffness (GA L^2 / EI up to 1e6
    !> times the stress terms, whose round-off the difference would keep). Without `loaded`:
    !> the elastic rod again.
    subroutine se3_stress_only(this, available, loaded)
        class(se3_pg_t), intent(inout) :: this
        logical, intent(out) :: available
        real(rk), intent(in), optional :: loaded(:)
        real(rk) :: eps(6)
        integer :: e
        available = .true.
        if (allocated(this%held_stress)) deallocate(this%held_stress)
        if (.not. present(loaded)) return
        allocate(this%held_stress(6, this%n_elements))
        do e = 1, this%n_elements
            call se3_strains(this%element_length(e), loaded(6 * (e - 1) + 1:6 * (e + 1)), eps)
            this%held_stress(:, e) = this%stiffness(:, e) * (eps - this%eps_ref(:, e))
        end do
    end subroutine se3_stress_only

    ! ---- Small helpers ----------------------------------------------------------------------

    pure function tinv(psi) result(t)
        use rs_math_so3, only: tangent_inverse_so3
        real(rk), intent(in) :: psi(3)
        real(rk) :: t(3, 3)
        t = tangent_inverse_so3(psi)
    end function tinv

    !> The unit vectors e_j, j in `columns`, as the columns of a 3 x 3 matrix.
    pure function identity_columns(columns) result(e)
        integer, intent(in) :: columns(3)
        real(rk) :: e(3, 3)
        integer :: j
        e = 0.0_rk
        do j = 1, 3
            e(columns(j), j) = 1.0_rk
        end do
    end function identity_columns

end module rs_se3_pg
