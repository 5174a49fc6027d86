#include "rs_macros.h"
!> The mixed port-Hamiltonian director rod of seed 000 (methods/ph_director_3d.md), as a
!> rod formulation: mesh, unknowns and their map, loads, the midpoint step problem assembled
!> from the pure kernels of rs_ph_director_element, and what is recorded.
!>
!> Unknowns of a step (uncondensed, methods §5.6): per free node q = (phi, d1, d2, d3) and
!> v at t_{n+1} (12 + 12) and the midpoint multipliers lambda (6); per element the stress
!> coefficients sigma at t_{n+1} (6 p). Supports hold by elimination (the Dirichlet conditions
!> of methods §2.9, issue 26 items 2 and 3; rs_model_support): a held coordinate of phi and its
!> velocity are not unknowns (held at the reference, v = 0), a held rotation takes the
!> directors, their velocities and the node's multipliers out (its constraint rows are void).
!> A clamped node has no unknowns, a pinned one holds phi, a sliding or held one what it holds.
!> A driven node (a clamp moved in time, rs_formulations_end_drive) has no unknowns either:
!> its q is prescribed by the drive, its velocity is the one the midpoint rule implies,
!> v_{n+1} = 2 (q_{n+1} - q_n)/h - v_n (the kinematic rows R_K with the prescribed q), and the
!> drive's work is booked from the reaction (accept_step). The state X has the layout of the
!> uncondensed unknown Y followed by the velocities of the driven nodes (12 each, the only
!> state that is no unknown); the lambda slots of X hold the multipliers of the last step's
!> midpoint, which no residual uses (methods §5.2, last bullet).
!>
!> Dofs are numbered node by node along the rod with each element's stresses after its
!> interior nodes, so the Jacobian is banded before any reordering.
!>
!> One object is one rod (issue 22): joints, end plates and contact between rods are couplings
!> of the system layer (src/system/), which reads the rod only through `nodes` (where each
!> node's q is in X and Y, and which rows its generalized forces enter) and `new_tie` (the
!> constraint rows of rs_ph_director_tie); the record ledger of the system layer sums the
!> energy terms that accept_step returns.
module rs_ph_director
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: str
    use rs_model_scene, only: scene_t, rod_input_t, unset_real, load_applies_to, &
        body_inertia_tensor, inertia_tensor, element_properties, axial_reference
    use rs_model_damping, only: kv_axial, kv_shear1, kv_shear2, kv_bend1, kv_bend2, kv_torsion
    use rs_model_rod_geometry, only: rod_geometry_t, rod_geometry_of, centreline_point, &
        centreline_frame
    use rs_core_logger, only: log_info, log_warning
    use rs_model_time_function, only: time_function_t, time_function_from_load, &
        time_function_from_actuator
    use rs_model_rod_history, only: rod_history_t
    use rs_assembly_csr_pattern, only: csr_builder_t, csr_pattern_t
    use rs_formulations_formulation, only: rod_formulation_t, formulation_traits_t, state_valid, &
        state_invalid, state_measures_t, rod_nodes_t, node_tie_t, modal_first_order
    use rs_formulations_energy_sentinel, only: step_energy_t, energy_consistent, energy_unchecked
    use rs_ph_director_element, only: ph_director_basis_t, ph_director_material_t, &
        ph_director_actuation_t, ph_director_max_branches, ph_director_max_tendons, &
        ph_director_basis_init, ph_director_element_residual, ph_director_node_residual, &
        ph_director_element_kinetic_energy, ph_director_element_complementary_energy, &
        ph_director_element_momenta, ph_director_element_position_integral, &
        ph_director_element_external_work, ph_director_node_external_work, &
        ph_director_node_constraint, ph_director_element_strains, &
        ph_director_element_dissipation, ph_director_element_actuator_work, &
        ph_director_element_damping_dissipation, ph_director_local_size, ph_director_element_reference_strains, &
        ph_director_element_initial_stress, ph_director_straight_strain
    use rs_ph_director_node_tie, only: ph_director_node_tie
    use rs_ph_director_follower, only: ph_director_follower_vector, ph_director_node_follower, &
        ph_director_element_follower, ph_director_element_follower_work
    use rs_model_support, only: end_hold, held_coordinates, coordinate_hold_refusal
    use rs_formulations_end_drive, only: end_drive_t, end_drive_init
    use rs_ph_director_body, only: ph_director_body_t, ph_director_body_init, &
        ph_director_body_kinetic_energy, ph_director_body_momenta, ph_director_body_weight, &
        ph_director_body_centre
    implicit none
    private

    !> Dofs of a node in the local layout of the node kernel: q (1:12), v (13:24), lambda (25:30).
    integer, parameter :: node_dofs = 30

    !> A concentrated load at a node, or a distributed load (per unit length) on the whole rod.
    type :: rod_load_t
        integer :: node = 0
        logical :: distributed = .false.
        !> Gravity (distributed): its acceleration, for the weight of a body on an end.
        logical :: gravity = .false.
        !> A follower load (&load frame = 'follower'): force and moment are components in the
        !> director basis (rs_ph_director_follower).
        logical :: follower = .false.
        real(rk) :: acceleration(3) = 0.0_rk
        real(rk) :: force(3) = 0.0_rk
        real(rk) :: moment(3) = 0.0_rk
        type(time_function_t) :: factor
    end type rod_load_t

    !> A pneumatic chamber or a tendon (methods §3.2): tau(t) = amplitude f(t) at material
    !> offset (rho^1, rho^2).
    type :: rod_actuator_t
        logical :: tendon = .false.
        real(rk) :: offset(2) = 0.0_rk
        real(rk) :: amplitude = 0.0_rk
        type(time_function_t) :: factor
    end type rod_actuator_t

    !> Where the dense Jacobians of a family of blocks (the elements, or the nodes) go in the
    !> CSR values: block b writes entry local(n) of its Jacobian (column-major index) to
    !> values(position(n)), n = first(b) .. first(b + 1) - 1. Only the entries of the block's
    !> mask between unknowns are listed, so entries outside the pattern and held entries
    !> cost nothing. The first n_assigned(b) entries of a block are the first contributions to
    !> their positions in assembly order (all elements, then all nodes), and are assigned
    !> rather than added: the values need no zeroing (every position of the pattern comes from
    !> a block's mask), and each sum is formed in the order of the entry-by-entry assembly.
    type :: scatter_t
        integer, allocatable :: first(:), n_assigned(:), local(:), position(:)
    end type scatter_t

    !> The ph_director formulation of one rod.
    type, extends(rod_formulation_t), public :: ph_director_t
        ! Parameters (read-only after init).
        character(len=:), allocatable :: name
        integer :: n_elements = 0
        integer :: degree = 2
        integer :: n_nodes = 0
        integer :: n_local = 0
        integer :: n_dofs = 0
        real(rk) :: length = 0.0_rk
        real(rk), allocatable :: node_s(:)
        real(rk), allocatable :: element_length(:)
        type(ph_director_basis_t) :: basis
        !> The rod's material (&rod values): its branches, constraints and drags are every
        !> element's.
        type(ph_director_material_t) :: material
        !> Each element's material: the rod's with the element's stiffnesses and inertias
        !> (&segment, issue 26 item 5); what the element kernels read.
        type(ph_director_material_t), allocatable :: element_material(:)
        !> Each element's mass per unit length as given (line_mass per element), for its weight.
        real(rk), allocatable :: element_line_mass(:)
        type(rod_load_t), allocatable :: loads(:)
        type(rod_actuator_t), allocatable :: actuators(:)
        !> Quasistatic run: no mass terms, time is a load factor, endpoint solve at the end.
        logical :: quasistatic = .false.
        !> Mass per unit length of the rod as given (rhoA), for its weight, a distributed force
        !> n̄ = rhoA g of eq. (12a) (methods/ph_director_3d.md §2.5): the material's rhoA is zero
        !> in a quasistatic run (no inertia, §6.3), the weight is not (issue 21 item 9).
        real(rk) :: line_mass = 0.0_rk
        !> The next step is the endpoint equilibrium at load time t_static (DESIGN.md §3).
        logical :: static = .false.
        real(rk) :: t_static = 0.0_rk
        !> The endpoint equilibrium is a continuation (set_step_problem with continue_from): a
        !> step to the pseudo-time tau solves R(Y) = (1 - tau) anchor, its rows scaled by
        !> row_scale (always 1: the rows of a step of length 1).
        logical :: continuing = .false.
        real(rk) :: row_scale = 0.0_rk
        real(rk), allocatable :: anchor(:)
        !> held(:, k): what the support of node k holds (rs_model_support held_coordinates:
        !> phi's x, y, z, then the rotation three times; module header).
        logical, allocatable :: held(:, :)
        !> Driven ends (rs_formulations_end_drive; frame: the reference directors), the drive
        !> of each node (0: none) and where the state holds a driven node's velocities
        !> (drive_state(k) .. drive_state(k) + 11, after the n_dofs entries of Y; 0: none).
        type(end_drive_t), allocatable :: drives(:)
        integer, allocatable :: drive_of(:), drive_state(:)
        !> Rigid bodies on the ends (&bc kind = 'body'; rs_ph_director_body).
        type(ph_director_body_t), allocatable :: bodies(:)
        real(rk), allocatable :: fixed_q(:, :)
        !> Reference strains eps_0 at the Gauss points, eps_ref(6, n_gauss, element).
        real(rk), allocatable :: eps_ref(:, :, :)
        !> Initial nodal velocities (12, node) and elastic stresses (6, p, element).
        real(rk), allocatable :: initial_v(:, :), initial_s(:, :, :)
        !> node_dof(i, k): unknown index of local dof i of node k (0: fixed or dropped).
        integer, allocatable :: node_dof(:, :)
        !> stress_dof(j, e): unknown index of stress coefficient j = 6 (b - 1) + component.
        integer, allocatable :: stress_dof(:, :)
        !> element_dof(i, e): unknown index of local dof i of element e (0: fixed).
        integer, allocatable :: element_dof(:, :)
        !> Stresses and velocities eliminated from the Newton unknowns (methods §5.5).
        logical :: condensed = .false.
        !> Condensed unknowns: node_unknown(i, k) for q (1:12) and lambda (13:18) of node k.
        integer, allocatable :: node_unknown(:, :)
        integer :: n_condensed = 0
        !> Inverse of each element's stress matrix C_e (constant: R_S is linear in sigma).
        real(rk), allocatable :: compliance_inverse(:, :, :)
        type(csr_pattern_t) :: pattern
        !> Uncondensed step: the scatter of the element and of the node Jacobians.
        type(scatter_t) :: element_scatter, node_scatter
        !> Condensed step: position in the CSR values of element entry (i, j) of element e and
        !> of node entry (i, j) of node k (0: not stored).
        integer, allocatable :: element_map(:, :, :)
        integer, allocatable :: node_map(:, :, :)
        ! Workspace (nodal fields at t_n and t_{n+1}, stresses).
        real(rk), allocatable :: q_n(:, :), q_1(:, :), v_n(:, :), v_1(:, :), lambda(:, :)
        !> Stress coefficients s(6, p, 0:n_branches, element) (0: elastic branch).
        real(rk), allocatable :: s_n(:, :, :, :), s_1(:, :, :, :)
        !> The mesh-resolution warning of `record` was given.
        logical :: warned_coarse = .false.
    contains
        procedure :: init => ph_director_init
        procedure :: n_state => ph_director_n_dofs
        procedure :: n_unknown => ph_director_n_unknown
        procedure :: predictor => ph_director_predictor
        procedure :: update => ph_director_update
        procedure :: jacobian_pattern => ph_director_jacobian_pattern
        procedure :: initial_state => ph_director_initial_state
        procedure :: step_residual => ph_director_step_residual
        procedure :: step_jacobian => ph_director_step_jacobian
        procedure :: accept_step => ph_director_accept_step
        procedure :: init_history => ph_director_init_history
        procedure :: record => ph_director_record
        procedure :: describe => ph_director_describe
        procedure :: energy => ph_director_energy
        procedure :: traits => ph_director_traits
        procedure :: set_step_problem => ph_director_set_step_problem
        procedure :: state_measures => ph_director_state_measures
        procedure :: nodes => ph_director_nodes
        procedure :: rest_state => ph_director_rest_state
        procedure :: path_weights => ph_director_path_weights
        procedure :: error_entries => ph_director_error_entries
        procedure :: new_tie => ph_director_new_tie
        procedure :: unpack
        procedure :: element_nodes
    end type ph_director_t

contains

    !> Build the rod rods(1) of a validated scene (an object is one rod: module header).
    subroutine ph_director_init(this, scene, rods, err)
        class(ph_director_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:)
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: message
        logical :: ok
        integer :: e, k, rod_index
        ! Joints between ph_director rods are ties of the system layer (DESIGN.md §5), never
        ! shared unknowns of one object.
        if (size(rods) /= 1) then
            RS_SET_ERROR(err, 'ph_director%init', 'ph_director rods cannot be joined yet')
            return
        end if
        rod_index = rods(1)
        associate (rod => scene%rods(rod_index))
            this%name = trim(rod%name)
            this%n_elements = rod%n_elements
            this%degree = rod%degree
            this%n_nodes = this%n_elements * this%degree + 1
            this%length = rod%length
            call ph_director_basis_init(this%basis, rod%degree, rod%n_gauss, ok)
            if (.not. ok) then
                message = 'rod ''' // this%name // ''': no element of degree ' // &
                    str(rod%degree) // ' with ' // str(rod%n_gauss) // ' Gauss points'
                RS_SET_ERROR(err, 'ph_director_init', message)
                return
            end if
            this%quasistatic = scene%time%quasistatic
            this%line_mass = rod%rhoA
            call build_material(this, rod, element_properties(scene, rod, this%n_elements), err)
            RS_RETURN_IF_ERROR(err)
            this%n_local = ph_director_local_size(this%basis, this%material)

            ! Uniform mesh in the arc length of the reference centreline (seed 000 §2.1).
            allocate(this%node_s(this%n_nodes), this%element_length(this%n_elements))
            this%node_s = [(rod%length * real(k - 1, rk) / real(this%n_nodes - 1, rk), &
                k = 1, this%n_nodes)]
            do e = 1, this%n_elements
                this%element_length(e) = this%node_s(e * this%degree + 1) - &
                    this%node_s((e - 1) * this%degree + 1)
            end do
            call reference_configuration(this, rod)
            call read_supports(this, scene, err)
            RS_RETURN_IF_ERROR(err)
            call read_loads(this, scene, err)
            RS_RETURN_IF_ERROR(err)
            call read_actuators(this, scene, err)
            RS_RETURN_IF_ERROR(err)
        end associate
        this%condensed = scene%solver%condense_stresses
        if (this%condensed .and. (any(this%material%compliance == 0.0_rk) .or. &
            this%material%n_branches > 0 .or. this%quasistatic .or. &
            scene%time%initial_equilibrium)) then
            ! Condensation needs an invertible, step-independent stress block and the dynamic
            ! kinematic rows (methods §5.5); the continued equilibrium (quasistatics, the
            ! initial equilibrium) has the stresses among its unknowns.
            call log_info('rod ''' // this%name // ''': condense_stresses ignored: ' // &
                'constrained components, Maxwell branches, a quasistatic run or an initial ' // &
                'equilibrium keep the stresses as unknowns')
            this%condensed = .false.
        end if
        call number_dofs(this)
        if (this%condensed) then
            call invert_compliances(this)
            call build_condensed_pattern(this)
        else
            call build_pattern(this)
        end if
        allocate(this%q_n(12, this%n_nodes), this%q_1(12, this%n_nodes), &
            this%v_n(12, this%n_nodes), this%v_1(12, this%n_nodes), &
            this%lambda(6, this%n_nodes), source=0.0_rk)
        allocate(this%s_n(6, this%degree, 0:this%material%n_branches, this%n_elements), &
            this%s_1(6, this%degree, 0:this%material%n_branches, this%n_elements), source=0.0_rk)
    end subroutine ph_director_init

    !> Inertia, compliances and Maxwell branches of a rod (methods §2.3, §2.4, §3.1): the
    !> stiffnesses k = (GA1, GA2, EA, EI1, EI2, GJ) are split into the elastic branch
    !> (1 - sum f_i) k and the branches f_i k with viscosities V_i = diag(tau) f_i k, tau =
    !> (tau_G, tau_G, tau_E, tau_E, tau_E, tau_G) (Remark 5.1). Constrained components
    !> (`kirchhoff`: shear; `inextensible`: shear and dilatation) are rigid: zero compliance,
    !> their stress a multiplier, no branch. A quasistatic run has no mass terms.
    !> Damping (docs/theory/ph_director.md "Damping"): the Kelvin-Voigt viscosity
    !> V = diag(tau_i k_i) with the rod's full stiffnesses k (all branches together), none for a
    !> rigid component (its strain rate is zero, so is its viscous stress); the drags as given.
    !> Each element's material is the same with the element's stiffnesses and inertias
    !> `properties` (rs_model_scene element_properties: EA, GA1, GA2, EI1, EI2, GJ, rhoA, rhoI1,
    !> rhoI2 per element).
    subroutine build_material(this, rod, properties, err)
        type(ph_director_t), intent(inout) :: this
        type(rod_input_t), intent(in) :: rod
        real(rk), intent(in) :: properties(:, :)
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: message
        real(rk) :: tau(6), elastic_fraction
        logical :: rigid(6)
        integer :: nb, br, e, i, j
        !> The stiffnesses in the order of the stress components (N1, N2, N3, M1, M2, M3).
        character(len=3), parameter :: rigid_names(6) = [character(len=3) :: 'GA1', 'GA2', &
            'EA', 'EI1', 'EI2', 'GJ']
        ! &rod kelvin_voigt_time is in the order (EA, GA1, GA2, EI1, EI2, GJ); these stresses
        ! are (N1, N2, N3, M1, M2, M3) = (GA1, GA2, EA, EI1, EI2, GJ).
        integer, parameter :: kv_order(6) = [kv_shear1, kv_shear2, kv_axial, kv_bend1, &
            kv_bend2, kv_torsion]
        rigid = .false.
        select case (trim(rod%constraint))
        case ('none')
        case ('kirchhoff')
            rigid(1:2) = .true.
        case ('inextensible')
            rigid(1:3) = .true.
        case default
            message = 'rod ''' // this%name // ''': unknown constraint ''' // trim(rod%constraint) // ''''
            RS_SET_ERROR(err, 'build_material', message)
            return
        end select
        ! &rod rigid (issue 26 item 2): any further infinite stiffnesses, the singular
        ! compliance of methods §2.3 with those entries zero.
        do i = 1, size(rod%rigid)
            if (len_trim(rod%rigid(i)) == 0) cycle
            j = findloc(rigid_names, trim(rod%rigid(i)), 1)
            if (j == 0) then
                message = 'rod ''' // this%name // ''': unknown rigid stiffness ''' // trim(rod%rigid(i)) // ''''
                RS_SET_ERROR(err, 'build_material', message)
                return
            end if
            rigid(j) = .true.
        end do
        nb = count(rod%maxwell_fraction /= unset_real)
        if (nb > ph_director_max_branches) then
            message = 'rod ''' // this%name // ''': at most ' // str(ph_director_max_branches) // &
                ' Maxwell branches'
            RS_SET_ERROR(err, 'build_material', message)
            return
        end if
        elastic_fraction = 1.0_rk - sum(rod%maxwell_fraction(1:nb))
        this%material%n_branches = nb
        this%material%drag = rod%drag
        this%material%angular_drag = rod%angular_drag
        call fill(this%material, [rod%GA1, rod%GA2, rod%EA, rod%EI1, rod%EI2, rod%GJ], &
            rod%rhoA, [rod%rhoI1, rod%rhoI2])
        allocate(this%element_material(this%n_elements), this%element_line_mass(this%n_elements))
        do e = 1, this%n_elements
            this%element_material(e) = this%material
            associate (p => properties(:, e))
                call fill(this%element_material(e), [p(2), p(3), p(1), p(4), p(5), p(6)], p(7), &
                    [p(8), p(9)])
                this%element_line_mass(e) = p(7)
            end associate
        end do
    contains
        !> The stiffness- and inertia-dependent parts of `material`; stiffness in the order of
        !> the stresses (GA1, GA2, EA, EI1, EI2, GJ).
        subroutine fill(material, stiffness, rho_a, rho_i)
            type(ph_director_material_t), intent(inout) :: material
            real(rk), intent(in) :: stiffness(6), rho_a, rho_i(2)
            if (.not. this%quasistatic) then
                material%rhoA = rho_a
                material%rhoI = rho_i
            end if
            material%compliance = 0.0_rk
            where (.not. rigid) material%compliance = 1.0_rk / (elastic_fraction * stiffness)
            do br = 1, nb
                tau = [rod%maxwell_tau_G(br), rod%maxwell_tau_G(br), rod%maxwell_tau_E(br), &
                    rod%maxwell_tau_E(br), rod%maxwell_tau_E(br), rod%maxwell_tau_G(br)]
                material%branch_active(1:6, br) = .not. rigid
                where (.not. rigid)
                    material%branch_compliance(1:6, br) = 1.0_rk / (rod%maxwell_fraction(br) * stiffness)
                    material%branch_fluidity(1:6, br) = &
                        1.0_rk / (tau * rod%maxwell_fraction(br) * stiffness)
                end where
            end do
            ! An unresolved time (a scene built in code) is no viscosity.
            tau = rod%kelvin_voigt_time(kv_order)
            material%viscosity = 0.0_rk
            where (.not. rigid .and. tau /= unset_real .and. tau > 0.0_rk) &
                material%viscosity = tau * stiffness
        end subroutine fill
    end subroutine build_material

    !> The actuators of this rod (methods §3.2): tau = -pressure area f(t) for a pneumatic
    !> chamber (a pressurized chamber pushes its end caps apart), tension f(t) for a tendon.
    subroutine read_actuators(this, scene, err)
        type(ph_director_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: message
        type(rod_actuator_t) :: actuator
        integer :: i
        allocate(this%actuators(0))
        if (.not. allocated(scene%actuators)) return
        do i = 1, size(scene%actuators)
            associate (input => scene%actuators(i))
                if (trim(input%rod) /= this%name) cycle
                actuator = rod_actuator_t()
                call time_function_from_actuator(input, actuator%factor, err)
                RS_RETURN_IF_ERROR(err)
                actuator%offset = input%offset
                actuator%tendon = trim(input%kind) == 'tendon'
                if (actuator%tendon) then
                    actuator%amplitude = input%tension
                else
                    actuator%amplitude = -input%pressure * input%area
                end if
                this%actuators = [this%actuators, actuator]
            end associate
        end do
        if (count(this%actuators%tendon) > ph_director_max_tendons) then
            message = 'rod ''' // this%name // ''': at most ' // str(ph_director_max_tendons) // ' tendons'
            RS_SET_ERROR(err, 'read_actuators', message)
        end if
    end subroutine read_actuators

    !> The actuators at time t (methods §3.2): the pneumatic chambers' constant material stress
    !> sum tau (0, 0, 1, rho^2, -rho^1, 0) and the tendons as (tau, rho^1, rho^2).
    pure function actuation_at(this, t) result(actuation)
        type(ph_director_t), intent(in) :: this
        real(rk), intent(in) :: t
        type(ph_director_actuation_t) :: actuation
        real(rk) :: tau
        integer :: i
        do i = 1, size(this%actuators)
            tau = this%actuators(i)%amplitude * this%actuators(i)%factor%value(t)
            if (this%actuators(i)%tendon) then
                actuation%n_tendons = actuation%n_tendons + 1
                actuation%tendon(:, actuation%n_tendons) = [tau, this%actuators(i)%offset]
            else
                actuation%pneumatic = actuation%pneumatic + tau * [0.0_rk, 0.0_rk, 1.0_rk, &
                    this%actuators(i)%offset(2), -this%actuators(i)%offset(1), 0.0_rk]
            end if
        end do
    end function actuation_at

    !> The reference configuration from the rod's geometry (rs_model_rod_geometry): nodal
    !> phi at equal arc length along the centreline, d3 the unit tangent, d1 parallel-transported
    !> from its value at s = 0, d2 = d3 x d1. The reference strains at the Gauss points are
    !> those of these nodes (stress-free, docs/theory/ph_director.md), or with `prestressed`
    !> the straight Gamma_0 = (0, 0, 1), K_0 = 0 with the consistent elastic stresses as
    !> initial stresses (methods §5.4). A prestrained rod (&rod prestrain) has its reference
    !> force strains Gamma_0 divided by 1 + prestrain (the stress-free rod is the given one
    !> shortened with the same shape, per unit given length; docs/theory/
    !> prestretched_starts.md) and starts with the consistent stresses too. The initial
    !> velocity is the rigid motion v_phi =
    !> velocity + omega x (phi - rotation_center), v_di = omega x d_i.
    subroutine reference_configuration(this, rod)
        type(ph_director_t), intent(inout) :: this
        type(rod_input_t), intent(in) :: rod
        type(rod_geometry_t) :: geometry
        real(rk) :: d(3, 3), center(3), omega(3)
        integer :: k, e, g, i, nodes(2)
        geometry = rod_geometry_of(rod)
        allocate(this%fixed_q(12, this%n_nodes), this%initial_v(12, this%n_nodes))
        do k = 1, this%n_nodes
            d = centreline_frame(geometry, this%node_s(k))
            this%fixed_q(1:3, k) = centreline_point(geometry, this%node_s(k))
            this%fixed_q(4:6, k) = d(:, 1)
            this%fixed_q(7:9, k) = d(:, 2)
            this%fixed_q(10:12, k) = d(:, 3)
        end do
        allocate(this%eps_ref(6, this%basis%n_gauss, this%n_elements))
        allocate(this%initial_s(6, this%degree, this%n_elements), source=0.0_rk)
        do e = 1, this%n_elements
            nodes = this%element_nodes(e)
            if (rod%prestressed) then
                do g = 1, this%basis%n_gauss
                    this%eps_ref(:, g, e) = ph_director_straight_strain
                end do
            else
                call ph_director_element_reference_strains(this%basis, this%element_length(e), &
                    this%fixed_q(:, nodes(1):nodes(2)), this%eps_ref(:, :, e))
            end if
            this%eps_ref(1:3, :, e) = axial_reference(rod) * this%eps_ref(1:3, :, e)
            if (rod%prestressed .or. rod%prestrain /= 0.0_rk) &
                call ph_director_element_initial_stress(this%basis, this%element_material(e), &
                this%element_length(e), this%fixed_q(:, nodes(1):nodes(2)), &
                this%eps_ref(:, :, e), this%initial_s(:, :, e))
        end do
        center = rod%rotation_center
        if (center(1) == unset_real) center = rod%start
        omega = rod%angular_velocity
        do k = 1, this%n_nodes
            this%initial_v(1:3, k) = rod%velocity + cross(omega, this%fixed_q(1:3, k) - center)
            do i = 1, 3
                this%initial_v(3 * i + 1:3 * i + 3, k) = cross(omega, this%fixed_q(3 * i + 1:3 * i + 3, k))
            end do
        end do
    contains
        pure function cross(a, b) result(c)
            real(rk), intent(in) :: a(3), b(3)
            real(rk) :: c(3)
            c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
        end function cross
    end subroutine reference_configuration

    !> The supports of the rod's ends: what each holds (rs_model_support; the coordinates of
    !> phi are inertial, so a slide's axis must be a coordinate axis), the drives of driven
    !> ends, the bodies on ends and on the tied end of a floating plate.
    subroutine read_supports(this, scene, err)
        type(ph_director_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: message
        type(end_drive_t) :: drive
        logical :: ok
        integer :: i, node
        allocate(this%held(6, this%n_nodes), source=.false.)
        allocate(this%drive_of(this%n_nodes), source=0)
        allocate(this%bodies(0), this%drives(0))
        do i = 1, size(scene%bcs)
            associate (bc => scene%bcs(i))
                if (trim(bc%rod) /= this%name) cycle
                node = merge(1, this%n_nodes, trim(bc%end) == 'start')
                select case (trim(bc%kind))
                case ('clamped', 'pinned', 'sliding', 'held', 'free')
                case ('driven')
                    call end_drive_init(drive, bc, node, this%fixed_q(1:3, node), &
                        reshape(this%fixed_q(4:12, node), [3, 3]), err)
                    RS_RETURN_IF_ERROR(err)
                    this%drives = [this%drives, drive]
                    this%drive_of(node) = size(this%drives)
                case ('body')
                    this%bodies = [this%bodies, ph_director_body_init(node, bc%mass, bc%centre, &
                        body_inertia_tensor(bc), reshape(this%fixed_q(4:12, node), [3, 3]))]
                case default
                    message = 'rod ''' // this%name // ''': a ''' // trim(bc%kind) // &
                        ''' end is not available for ph_director in this version (docs/user/capabilities.md)'
                    RS_SET_ERROR(err, 'read_supports', message)
                    return
                end select
                call held_coordinates(end_hold(bc), this%held(:, node), ok)
                if (.not. ok) then
                    message = coordinate_hold_refusal(this%name, 'ph_director', 'phi', bc)
                    RS_SET_ERROR(err, 'read_supports', message)
                    return
                end if
            end associate
        end do
        ! A floating plate (&plate mass > 0; issue 24 item 4) is a body on the tied end of its
        ! first rod; the other rods' ends are tied to that end rigidly (rs_system_tie_coupling).
        if (.not. allocated(scene%plates)) return
        do i = 1, size(scene%plates)
            associate (plate => scene%plates(i))
                if (plate%mass <= 0.0_rk .or. trim(plate%rods(1)) /= this%name) cycle
                node = merge(1, this%n_nodes, trim(plate%end) == 'start')
                this%bodies = [this%bodies, ph_director_body_init(node, plate%mass, &
                    plate%centre - this%fixed_q(1:3, node), &
                    inertia_tensor(plate%inertia, plate%inertia_products), &
                    reshape(this%fixed_q(4:12, node), [3, 3]))]
            end associate
        end do
    end subroutine read_supports

    subroutine read_loads(this, scene, err)
        type(ph_director_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: message
        type(rod_load_t) :: load
        integer :: i, n
        ! Sized once (appending one load at a time copies all before it: quadratic in a scene
        ! of thousands of &load groups, issue 21 item 17).
        allocate(this%loads(count([(load_applies_to(scene%loads(i), this%name), &
            i = 1, size(scene%loads))])))
        n = 0
        do i = 1, size(scene%loads)
            associate (input => scene%loads(i))
                if (.not. load_applies_to(input, this%name)) cycle
                load = rod_load_t()
                ! The input check refuses a follower weight (gravity is dead).
                load%follower = trim(input%frame) == 'follower'
                call time_function_from_load(input, load%factor, err)
                RS_RETURN_IF_ERROR(err)
                select case (trim(input%where))
                case ('start')
                    load%node = 1
                case ('end')
                    load%node = this%n_nodes
                case ('distributed')
                    load%distributed = .true.
                case ('gravity')
                    load%distributed = .true.
                end select
                if (trim(input%where) == 'gravity') then
                    load%force = this%line_mass * input%acceleration
                    load%gravity = .true.
                    load%acceleration = input%acceleration
                else
                    load%force = input%force
                    load%moment = input%moment
                end if
                n = n + 1
                this%loads(n) = load
            end associate
        end do
    end subroutine read_loads

    !> Unknown numbering: nodes along the rod, each element's stresses after its interior nodes.
    subroutine number_dofs(this)
        type(ph_director_t), intent(inout) :: this
        integer :: e, a, k, next
        allocate(this%node_dof(node_dofs, this%n_nodes), source=0)
        allocate(this%stress_dof(n_stress(this), this%n_elements), source=0)
        next = 0
        call number_node(1)
        do e = 1, this%n_elements
            do a = 2, this%degree
                call number_node((e - 1) * this%degree + a)
            end do
            do k = 1, n_stress(this)
                next = next + 1
                this%stress_dof(k, e) = next
            end do
            call number_node(e * this%degree + 1)
        end do
        this%n_dofs = next
        allocate(this%element_dof(this%n_local, this%n_elements))
        do e = 1, this%n_elements
            this%element_dof(:, e) = element_dofs(this, e)
        end do
        ! The driven nodes' velocities: state only, after the unknowns.
        allocate(this%drive_state(this%n_nodes), source=0)
        do a = 1, size(this%drives)
            this%drive_state(this%drives(a)%node) = this%n_dofs + 12 * (a - 1) + 1
        end do
    contains
        subroutine number_node(node)
            integer, intent(in) :: node
            integer :: i
            do i = 1, node_dofs
                if (is_held_dof(this, i, node)) cycle
                next = next + 1
                this%node_dof(i, node) = next
            end do
        end subroutine number_node
    end subroutine number_dofs

    !> Whether local dof i of node k (node kernel layout: q 1:12, v 13:24, lambda 25:30) is
    !> held by its support (module header): a held coordinate of phi or the held directors,
    !> with their velocities, and the multipliers of a held rotation.
    pure logical function is_held_dof(this, i, k) result(held)
        type(ph_director_t), intent(in) :: this
        integer, intent(in) :: i, k
        if (i <= 12) then
            held = this%held(min(i, 4), k)
        else if (i <= 24) then
            held = this%held(min(i - 12, 4), k)
        else
            held = this%held(4, k)
        end if
    end function is_held_dof

    !> The held q of node k (its reference, or a driven node's pose at time t; without t the
    !> reference pose).
    pure function held_q(this, k, t) result(q)
        type(ph_director_t), intent(in) :: this
        integer, intent(in) :: k
        real(rk), intent(in), optional :: t
        real(rk) :: q(12)
        real(rk) :: frame(3, 3)
        q = this%fixed_q(:, k)
        if (this%drive_of(k) == 0 .or. .not. present(t)) return
        call this%drives(this%drive_of(k))%pose(t, q(1:3), frame)
        q(4:12) = reshape(frame, [9])
    end function held_q

    !> Stress coefficients of an element: 6 p per branch, elastic branch included.
    pure integer function n_stress(this)
        type(ph_director_t), intent(in) :: this
        n_stress = 6 * this%degree * (1 + this%material%n_branches)
    end function n_stress

    !> Whether stress unknown j of an element (1 .. n_stress) is a live component: elastic
    !> components always, branch components unless the component is rigid.
    pure logical function stress_active(this, j)
        type(ph_director_t), intent(in) :: this
        integer, intent(in) :: j
        integer :: br
        br = (j - 1) / (6 * this%degree)
        stress_active = .true.
        if (br > 0) stress_active = this%material%branch_active(mod(j - 1, 6) + 1, br)
    end function stress_active

    !> Global unknown index of every local dof of element e (0 where fixed).
    pure function element_dofs(this, e) result(dofs)
        type(ph_director_t), intent(in) :: this
        integer, intent(in) :: e
        integer :: dofs(this%n_local)
        integer :: a, node
        do a = 1, this%degree + 1
            node = (e - 1) * this%degree + a
            dofs(24 * (a - 1) + 1 : 24 * a) = this%node_dof(1:24, node)
        end do
        dofs(24 * (this%degree + 1) + 1 :) = this%stress_dof(:, e)
    end function element_dofs

    !> Which element Jacobian entries can be non-zero (methods §5.6 table, with the non-rate
    !> stress rows of the kernel): momentum rows couple to all q, to the live stresses and,
    !> through the mass and the drag (neither in a quasistatic run), to v of the same
    !> component (the Kelvin-Voigt stress couples them to the q of the element only); stress rows
    !> couple to all q and to the stresses of the same component and branch; the stress of a
    !> rigid component's branch only to itself.
    pure function element_mask(this) result(mask)
        type(ph_director_t), intent(in) :: this
        logical :: mask(this%n_local, this%n_local)
        integer :: n_node_local, i, j, ci, cj, si, sj
        logical :: has_mass
        n_node_local = 24 * (this%degree + 1)
        ! The drag, like the mass, couples a momentum row to the velocity of its component.
        has_mass = this%material%rhoA /= 0.0_rk .or. any(this%material%rhoI /= 0.0_rk) .or. &
            this%material%drag /= 0.0_rk .or. this%material%angular_drag /= 0.0_rk
        mask = .false.
        do j = 1, this%n_local
            do i = 1, this%n_local
                if (i <= n_node_local) then
                    ci = mod(i - 1, 24) + 1
                    if (ci <= 12) cycle
                    if (j > n_node_local) then
                        mask(i, j) = stress_active(this, j - n_node_local)
                    else
                        cj = mod(j - 1, 24) + 1
                        mask(i, j) = cj <= 12 .or. (cj == ci .and. has_mass)
                    end if
                else
                    si = i - n_node_local
                    if (.not. stress_active(this, si)) then
                        mask(i, j) = i == j
                    else if (j <= n_node_local) then
                        mask(i, j) = mod(j - 1, 24) + 1 <= 12
                    else
                        sj = j - n_node_local
                        mask(i, j) = mod(si - 1, 6) == mod(sj - 1, 6) .and. &
                            (si - 1) / (6 * this%degree) == (sj - 1) / (6 * this%degree)
                    end if
                end if
            end do
        end do
    end function element_mask

    !> Non-zeros of the node kernel's Jacobian (methods §5.6): kinematic rows couple q and v of
    !> the same component; director momentum rows couple to the directors (multiplier and
    !> end-moment terms) and the multipliers; constraint rows to the directors. On a rod with
    !> a body on an end, the momentum rows couple to all v (the body's mass matrix couples
    !> the point's and the directors' velocities).
    pure function node_mask(with_body, with_follower) result(mask)
        logical, intent(in) :: with_body, with_follower
        logical :: mask(node_dofs, node_dofs)
        integer :: c
        mask = .false.
        if (with_body) mask(13:24, 13:24) = .true.
        ! A follower end force turns with the directors (rs_ph_director_follower).
        if (with_follower) mask(13:15, 4:12) = .true.
        do c = 1, 12
            mask(c, c) = .true.
            mask(c, 12 + c) = .true.
        end do
        mask(16:24, 4:12) = .true.
        mask(16:24, 25:30) = .true.
        mask(25:30, 4:12) = .true.
    end function node_mask

    !> The Jacobian pattern (element_mask, node_mask) and the scatter of the kernels into it.
    subroutine build_pattern(this)
        type(ph_director_t), intent(inout) :: this
        type(csr_builder_t) :: builder
        logical :: emask(this%n_local, this%n_local), nmask(node_dofs, node_dofs)
        logical, allocatable :: touched(:)
        integer :: e, k
        emask = element_mask(this)
        nmask = node_mask(size(this%bodies) > 0, any(this%loads%follower .and. this%loads%node > 0))
        call builder%init(this%n_dofs, this%n_elements * count(emask) + this%n_nodes * count(nmask))
        do e = 1, this%n_elements
            call builder%add_block(this%element_dof(:, e), this%element_dof(:, e), emask)
        end do
        do k = 1, this%n_nodes
            call builder%add_block(this%node_dof(:, k), this%node_dof(:, k), nmask)
        end do
        call builder%build(this%pattern)
        allocate(touched(this%pattern%nnz()), source=.false.)
        call build_scatter(this%pattern, this%element_dof, emask, touched, this%element_scatter)
        call build_scatter(this%pattern, this%node_dof, nmask, touched, this%node_scatter)
    end subroutine build_pattern

    !> The scatter (scatter_t) of the blocks b with unknowns dofs(:, b) (0: none) and the mask
    !> of their non-zeros, in assembly order after the positions already `touched`.
    subroutine build_scatter(pattern, dofs, mask, touched, scatter)
        type(csr_pattern_t), intent(in) :: pattern
        integer, intent(in) :: dofs(:, :)
        logical, intent(in) :: mask(:, :)
        logical, intent(inout) :: touched(:)
        type(scatter_t), intent(out) :: scatter
        integer :: local(count(mask)), position(count(mask))
        logical :: fresh(count(mask))
        integer :: b, i, j, m, n, n_fresh
        allocate(scatter%first(size(dofs, 2) + 1), scatter%n_assigned(size(dofs, 2)))
        allocate(scatter%local(size(dofs, 2) * count(mask)), &
            scatter%position(size(dofs, 2) * count(mask)))
        n = 0
        do b = 1, size(dofs, 2)
            m = 0
            do j = 1, size(mask, 2)
                if (dofs(j, b) <= 0) cycle
                do i = 1, size(mask, 1)
                    if (dofs(i, b) <= 0 .or. .not. mask(i, j)) cycle
                    m = m + 1
                    local(m) = i + size(mask, 1) * (j - 1)
                    position(m) = pattern%position(dofs(i, b), dofs(j, b))
                end do
            end do
            ! A block's positions are distinct: its unknowns are.
            fresh(1:m) = .not. touched(position(1:m))
            touched(position(1:m)) = .true.
            n_fresh = count(fresh(1:m))
            scatter%first(b) = n + 1
            scatter%n_assigned(b) = n_fresh
            scatter%local(n + 1:n + n_fresh) = pack(local(1:m), fresh(1:m))
            scatter%position(n + 1:n + n_fresh) = pack(position(1:m), fresh(1:m))
            scatter%local(n + n_fresh + 1:n + m) = pack(local(1:m), .not. fresh(1:m))
            scatter%position(n + n_fresh + 1:n + m) = pack(position(1:m), .not. fresh(1:m))
            n = n + m
        end do
        scatter%first(size(dofs, 2) + 1) = n + 1
        scatter%local = scatter%local(1:n)
        scatter%position = scatter%position(1:n)
    end subroutine build_scatter

    !> Write the dense Jacobian `block` (size_block entries, column-major) of block b into the
    !> CSR values through its scatter (scatter_t).
    pure subroutine scatter_block(scatter, b, size_block, block, values)
        type(scatter_t), intent(in) :: scatter
        integer, intent(in) :: b, size_block
        real(rk), intent(in) :: block(size_block)
        real(rk), intent(inout) :: values(:)
        integer :: n, last_assigned
        last_assigned = scatter%first(b) + scatter%n_assigned(b) - 1
        do n = scatter%first(b), last_assigned
            values(scatter%position(n)) = block(scatter%local(n))
        end do
        do n = last_assigned + 1, scatter%first(b + 1) - 1
            values(scatter%position(n)) = values(scatter%position(n)) + block(scatter%local(n))
        end do
    end subroutine scatter_block

    !> The nodes' positions and directors (q: the node kernel's 1:12). Not their velocities:
    !> the midpoint rule fixes only v_{n+1/2} = (v_n + v_{n+1})/2 (the kinematic rows
    !> h v_mid = q_{n+1} - q_n, methods/ph_director_3d.md §5.2), so the step-end velocities
    !> carry an undamped (-1)^n component that no position sees and that the divided
    !> differences would take for an O(1) error at any h (measured: the flying spaghetti's
    !> director velocities drove the steps to dt_min). Nor the orthonormality multipliers
    !> (25:30) and the element stresses, midpoint values.
    subroutine ph_director_error_entries(this, weigh)
        class(ph_director_t), intent(in) :: this
        logical, intent(out) :: weigh(:)
        integer :: k, i
        weigh = .false.
        do k = 1, this%n_nodes
            do i = 1, 12
                if (this%node_dof(i, k) > 0) weigh(this%node_dof(i, k)) = .true.
            end do
        end do
    end subroutine ph_director_error_entries

    !> The state: the uncondensed unknowns and the driven nodes' velocities (module header).
    pure integer function ph_director_n_dofs(this)
        class(ph_director_t), intent(in) :: this
        ph_director_n_dofs = this%n_dofs + 12 * size(this%drives)
    end function ph_director_n_dofs

    pure integer function ph_director_n_unknown(this)
        class(ph_director_t), intent(in) :: this
        if (this%condensed) then
            ph_director_n_unknown = this%n_condensed
        else
            ph_director_n_unknown = this%n_dofs
        end if
    end function ph_director_n_unknown

    subroutine ph_director_jacobian_pattern(this, row_ptr, cols)
        class(ph_director_t), intent(in) :: this
        integer, allocatable, intent(out) :: row_ptr(:), cols(:)
        call this%pattern%zero_based(row_ptr, cols)
    end subroutine ph_director_jacobian_pattern

    !> The reference configuration with its initial velocity and consistent stresses (methods
    !> §5.4): sigma = 0 in a stress-free reference, the projected elastic stresses of a
    !> prestressed one (Maxwell branches at 0); v the initial rigid motion (0 on held coordinates,
    !> which the input check keeps at rest); lambda = 0.
    subroutine ph_director_initial_state(this, x)
        class(ph_director_t), intent(in) :: this
        real(rk), intent(out) :: x(:)
        integer :: k, i, e
        x = 0.0_rk
        do k = 1, this%n_nodes
            do i = 1, 12
                if (this%node_dof(i, k) > 0) x(this%node_dof(i, k)) = this%fixed_q(i, k)
                if (this%node_dof(12 + i, k) > 0) x(this%node_dof(12 + i, k)) = this%initial_v(i, k)
            end do
            if (this%drive_state(k) > 0) x(this%drive_state(k):this%drive_state(k) + 11) = &
                this%initial_v(:, k)
        end do
        do e = 1, this%n_elements
            x(this%stress_dof(1:6 * this%degree, e)) = reshape(this%initial_s(:, :, e), &
                [6 * this%degree])
        end do
    end subroutine ph_director_initial_state

    !> Nodal q, v, lambda and element stresses of a state or an uncondensed unknown vector x at
    !> time t: held coordinates at their held values (held_q; a driven node's pose at t, the
    !> reference pose without t), held velocities zero, the multipliers of a held rotation zero;
    !> a driven node's velocities from a state, zero from an unknown vector (driven_velocities
    !> sets them).
    subroutine unpack(this, x, q, v, lambda, s, t)
        class(ph_director_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        real(rk), intent(out) :: q(:, :), v(:, :), lambda(:, :), s(:, :, 0:, :)
        real(rk), intent(in), optional :: t
        integer :: k, e, i, j, b, br
        do k = 1, this%n_nodes
            q(:, k) = held_q(this, k, t)
            v(:, k) = 0.0_rk
            lambda(:, k) = 0.0_rk
            do i = 1, 12
                if (this%node_dof(i, k) > 0) q(i, k) = x(this%node_dof(i, k))
                if (this%node_dof(12 + i, k) > 0) v(i, k) = x(this%node_dof(12 + i, k))
            end do
            do i = 1, 6
                if (this%node_dof(24 + i, k) > 0) lambda(i, k) = x(this%node_dof(24 + i, k))
            end do
            if (this%drive_state(k) > 0 .and. size(x) > this%n_dofs) &
                v(:, k) = x(this%drive_state(k):this%drive_state(k) + 11)
        end do
        do e = 1, this%n_elements
            j = 0
            do br = 0, this%material%n_branches
                do b = 1, this%degree
                    do i = 1, 6
                        j = j + 1
                        s(i, b, br, e) = x(this%stress_dof(j, e))
                    end do
                end do
            end do
        end do
    end subroutine unpack

    !> The velocities v_1 of the driven nodes in the workspace, from their prescribed q_n, q_1
    !> and v_n: the midpoint rule's v_1 = 2 (q_1 - q_n)/h - v_n (R_K = 0, methods §5.5 item 1),
    !> or v_1 = v_n in the endpoint equilibrium (its kinematic rows keep the velocities).
    subroutine driven_velocities(this, h)
        type(ph_director_t), intent(inout) :: this
        real(rk), intent(in) :: h
        integer :: i, k
        do i = 1, size(this%drives)
            k = this%drives(i)%node
            if (this%static) then
                this%v_1(:, k) = this%v_n(:, k)
            else
                this%v_1(:, k) = 2.0_rk * (this%q_1(:, k) - this%q_n(:, k)) / h - this%v_n(:, k)
            end if
        end do
    end subroutine driven_velocities

    !> First and last node of element e.
    pure function element_nodes(this, e) result(range)
        class(ph_director_t), intent(in) :: this
        integer, intent(in) :: e
        integer :: range(2)
        range = [(e - 1) * this%degree + 1, e * this%degree + 1]
    end function element_nodes

    !> The times of the state x_n and of the unknown Y of a step, at which driven nodes are
    !> placed: t_n and t_n + h, or both the load time of the endpoint equilibrium (whose steps
    !> are in a pseudo-time at that load time).
    pure function state_times(this, t_n, h) result(times)
        type(ph_director_t), intent(in) :: this
        real(rk), intent(in) :: t_n, h
        real(rk) :: times(2)
        times = [t_n, t_n + h]
        if (this%static) times = this%t_static
    end function state_times

    !> Time at which a step evaluates its loads and actuators: the mid time (methods §5.1), or
    !> the load time of the endpoint equilibrium.
    pure real(rk) function load_time(this, t_n, h)
        type(ph_director_t), intent(in) :: this
        real(rk), intent(in) :: t_n, h
        load_time = merge(this%t_static, t_n + 0.5_rk * h, this%static)
    end function load_time

    !> Distributed force and moment per unit length at time t, and the gravity acceleration
    !> (an element's weight per length is its own line mass times it, &segment): the dead ones
    !> as spatial vectors or, with `follower`, the follower ones as components in the director
    !> basis (gravity is dead: zero then).
    pure subroutine distributed_loads(this, t, follower, force, moment, gravity)
        type(ph_director_t), intent(in) :: this
        real(rk), intent(in) :: t
        logical, intent(in) :: follower
        real(rk), intent(out) :: force(3), moment(3), gravity(3)
        integer :: i
        real(rk) :: f
        force = 0.0_rk
        moment = 0.0_rk
        gravity = 0.0_rk
        do i = 1, size(this%loads)
            if (.not. this%loads(i)%distributed .or. (this%loads(i)%follower .neqv. follower)) cycle
            f = this%loads(i)%factor%value(t)
            if (this%loads(i)%gravity) then
                gravity = gravity + f * this%loads(i)%acceleration
            else
                force = force + f * this%loads(i)%force
            end if
            moment = moment + f * this%loads(i)%moment
        end do
    end subroutine distributed_loads

    !> Concentrated force and moment at node k and time t: the dead ones, or with `follower`
    !> the follower ones (components in the director basis).
    pure subroutine node_loads(this, k, t, follower, force, moment)
        type(ph_director_t), intent(in) :: this
        integer, intent(in) :: k
        real(rk), intent(in) :: t
        logical, intent(in) :: follower
        real(rk), intent(out) :: force(3), moment(3)
        integer :: i
        real(rk) :: f
        force = 0.0_rk
        moment = 0.0_rk
        do i = 1, size(this%loads)
            if (this%loads(i)%distributed .or. this%loads(i)%node /= k .or. &
                (this%loads(i)%follower .neqv. follower)) cycle
            f = this%loads(i)%factor%value(t)
            force = force + f * this%loads(i)%force
            moment = moment + f * this%loads(i)%moment
        end do
    end subroutine node_loads

    !> The generalized forces (12) at time t on node k of the bodies on it (their weight), and
    !> whether it carries a body.
    pure subroutine body_forces(this, k, t, force, carries)
        type(ph_director_t), intent(in) :: this
        integer, intent(in) :: k
        real(rk), intent(in) :: t
        real(rk), intent(out) :: force(12)
        logical, intent(out) :: carries
        real(rk) :: acceleration(3)
        integer :: b, i
        force = 0.0_rk
        carries = any(this%bodies%node == k)
        if (.not. carries) return
        acceleration = 0.0_rk
        do i = 1, size(this%loads)
            if (this%loads(i)%gravity) acceleration = acceleration + &
                this%loads(i)%factor%value(t) * this%loads(i)%acceleration
        end do
        do b = 1, size(this%bodies)
            if (this%bodies(b)%node /= k) cycle
            force = force + ph_director_body_weight(this%bodies(b), acceleration)
        end do
    end subroutine body_forces

    !> The midpoint step residual (methods §5.6, rows R_K, R_M, R_S and the nodal constraint
    !> g(d_{n+1}) = 0 of DESIGN.md §3), assembled from the element and node kernels.
    subroutine ph_director_step_residual(this, t_n, h, x_n, y, f, status)
        class(ph_director_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: f(:)
        integer, intent(out) :: status
        if (any(y /= y)) then
            status = state_invalid
            return
        end if
        status = state_valid
        if (this%condensed) then
            call condensed_step(this, t_n, h, x_n, y, f=f)
        else if (this%continuing) then
            ! The Newton homotopy of the continuation: t_n + h is the pseudo-time tau.
            call uncondensed_step(this, t_n, this%row_scale, x_n, y, f=f)
            f = f - max(0.0_rk, 1.0_rk - (t_n + h)) * this%anchor
        else
            call uncondensed_step(this, t_n, h, x_n, y, f=f)
        end if
    end subroutine ph_director_step_residual

    !> dF/dY of the step residual, written into the values of the fixed CSR pattern.
    subroutine ph_director_step_jacobian(this, t_n, h, x_n, y, values, status)
        class(ph_director_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: values(:)
        integer, intent(out) :: status
        status = state_valid
        if (this%condensed) then
            call condensed_step(this, t_n, h, x_n, y, values=values)
        else if (this%continuing) then
            call uncondensed_step(this, t_n, this%row_scale, x_n, y, values=values)
        else
            call uncondensed_step(this, t_n, h, x_n, y, values=values)
        end if
    end subroutine ph_director_step_jacobian

    !> The node kernel (methods §5.2 (K1), (K2), the multiplier and end-load terms, and the
    !> constraint g(d_{n+1})) of node k on the workspace fields, loads at t_load; a node whose
    !> rotation is held has no multipliers (their rows are identity rows, and dropped).
    subroutine node_kernel(this, k, h, t_load, r_k, j_k)
        type(ph_director_t), intent(in) :: this
        integer, intent(in) :: k
        real(rk), intent(in) :: h, t_load
        real(rk), intent(out) :: r_k(node_dofs)
        real(rk), intent(out), optional :: j_k(node_dofs, node_dofs)
        real(rk) :: force(3), moment(3)
        real(rk) :: weight(12), r_f(12), j_f(12, 12)
        integer :: b
        logical :: carries
        call node_loads(this, k, t_load, .false., force, moment)
        call ph_director_node_residual(h, this%static, this%q_n(:, k), this%q_1(:, k), &
            this%v_n(:, k), this%v_1(:, k), this%lambda(:, k), .not. this%held(4, k), force, &
            moment, r_k, j_k)
        ! Follower end loads at the midpoint directors (rs_ph_director_follower).
        call node_loads(this, k, t_load, .true., force, moment)
        if (any(force /= 0.0_rk) .or. any(moment /= 0.0_rk)) then
            if (present(j_k)) then
                call ph_director_node_follower(h, this%static, this%q_n(:, k), this%q_1(:, k), &
                    force, moment, r_f, j_f)
                j_k(13:24, 1:12) = j_k(13:24, 1:12) + j_f
            else
                call ph_director_node_follower(h, this%static, this%q_n(:, k), this%q_1(:, k), &
                    force, moment, r_f)
            end if
            r_k(13:24) = r_k(13:24) + r_f
        end if
        if (size(this%bodies) == 0) return
        ! A body on the node (rs_ph_director_body): its weight, and its inertia in time steps.
        call body_forces(this, k, t_load, weight, carries)
        if (.not. carries) return
        r_k(13:24) = r_k(13:24) - h * weight
        if (this%static .or. this%quasistatic) return
        do b = 1, size(this%bodies)
            if (this%bodies(b)%node /= k) cycle
            r_k(13:24) = r_k(13:24) + matmul(this%bodies(b)%mass_matrix, &
                this%v_1(:, k) - this%v_n(:, k))
            if (present(j_k)) j_k(13:24, 13:24) = j_k(13:24, 13:24) + this%bodies(b)%mass_matrix
        end do
    end subroutine node_kernel

    !> Residual and/or Jacobian of the uncondensed step: element kernels scattered through the
    !> dof map, node kernels for the kinematic, multiplier and end-load rows. A driven node has
    !> no rows: its momentum rows, the reaction of the drive, are no equations (accept_step
    !> books their work).
    subroutine uncondensed_step(this, t_n, h, x_n, y, f, values)
        type(ph_director_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out), optional :: f(:), values(:)
        real(rk) :: r_e(this%n_local), j_e(this%n_local, this%n_local)
        real(rk) :: r_k(node_dofs), j_k(node_dofs, node_dofs)
        real(rk) :: nbar(3), mbar(3), gravity(3), follower(6), no_gravity(3), t_mid, times(2)
        type(ph_director_actuation_t) :: actuation
        integer :: e, k, i
        times = state_times(this, t_n, h)
        call this%unpack(x_n, this%q_n, this%v_n, this%lambda, this%s_n, times(1))
        call this%unpack(y, this%q_1, this%v_1, this%lambda, this%s_1, times(2))
        call driven_velocities(this, h)
        t_mid = load_time(this, t_n, h)
        call distributed_loads(this, t_mid, .false., nbar, mbar, gravity)
        call distributed_loads(this, t_mid, .true., follower(1:3), follower(4:6), no_gravity)
        actuation = actuation_at(this, t_mid)
        if (present(f)) f = 0.0_rk
        ! No zeroing of the values: every position is assigned by its first block (scatter_t).
        do e = 1, this%n_elements
            if (present(values) .and. present(f)) then
                call element_kernel(this, e, h, nbar, gravity, mbar, follower, actuation, r_e, j_e)
            else if (present(values)) then
                call element_kernel(this, e, h, nbar, gravity, mbar, follower, actuation, j_e=j_e)
            else
                call element_kernel(this, e, h, nbar, gravity, mbar, follower, actuation, r_e)
            end if
            if (present(values)) call scatter_block(this%element_scatter, e, size(j_e), j_e, values)
            if (present(f)) then
                do i = 1, this%n_local
                    if (this%element_dof(i, e) > 0) f(this%element_dof(i, e)) = &
                        f(this%element_dof(i, e)) + r_e(i)
                end do
            end if
        end do
        do k = 1, this%n_nodes
            if (all(this%node_dof(:, k) == 0)) cycle
            if (present(values)) then
                call node_kernel(this, k, h, t_mid, r_k, j_k)
                call scatter_block(this%node_scatter, k, size(j_k), j_k, values)
            else
                call node_kernel(this, k, h, t_mid, r_k)
            end if
            if (present(f)) then
                do i = 1, node_dofs
                    if (this%node_dof(i, k) > 0) f(this%node_dof(i, k)) = &
                        f(this%node_dof(i, k)) + r_k(i)
                end do
            end if
        end do
    end subroutine uncondensed_step

    ! ---- Condensed step (methods §5.5) ----------------------------------------------------
    ! With q_{n+1} and the midpoint multipliers as the only unknowns, the kinematic rows R_K
    ! give v_{n+1} = 2 (q_{n+1} - q_n)/h - v_n and the stress rows R_S, linear in sigma_{n+1}
    ! with the constant matrix C_e, give sigma_{n+1} element by element. The residual is R_M
    ! and the constraint rows at that (v, sigma), so R_K = R_S = 0 exactly and the norm of the
    ! residual is the norm of the uncondensed one (DESIGN.md §3). The Jacobian is the element
    ! Schur complement of the uncondensed one.

    !> Number the condensed unknowns (q, lambda of each free node) along the rod.
    subroutine number_condensed(this)
        type(ph_director_t), intent(inout) :: this
        integer :: k, i, next
        allocate(this%node_unknown(18, this%n_nodes), source=0)
        next = 0
        do k = 1, this%n_nodes
            do i = 1, 18
                if (is_held_dof(this, merge(i, 12 + i, i <= 12), k)) cycle
                next = next + 1
                this%node_unknown(i, k) = next
            end do
        end do
        this%n_condensed = next
    end subroutine number_condensed

    !> C_e^{-1} of every element, read off the kernel's stress block (R_S is linear in sigma).
    subroutine invert_compliances(this)
        type(ph_director_t), intent(inout) :: this
        real(rk) :: q(12, this%degree + 1), v(12, this%degree + 1), s(6, this%degree, 0:0)
        real(rk) :: r_e(this%n_local), j_e(this%n_local, this%n_local)
        integer :: e, m, first
        m = 6 * this%degree
        first = 24 * (this%degree + 1) + 1
        allocate(this%compliance_inverse(m, m, this%n_elements))
        q = this%fixed_q(:, 1:this%degree + 1)
        v = 0.0_rk
        s = 0.0_rk
        do e = 1, this%n_elements
            call ph_director_element_residual(this%basis, this%element_material(e), &
                this%element_length(e), this%eps_ref(:, :, e), 1.0_rk, .false., q, q, v, v, s, s, [0.0_rk, 0.0_rk, 0.0_rk], &
                [0.0_rk, 0.0_rk, 0.0_rk], ph_director_actuation_t(), r_e, j_e)
            this%compliance_inverse(:, :, e) = inverse(j_e(first:, first:))
        end do
        call number_condensed(this)
    end subroutine invert_compliances

    !> Inverse of a small non-singular matrix (Gauss-Jordan with partial pivoting).
    pure function inverse(a) result(b)
        real(rk), intent(in) :: a(:, :)
        real(rk) :: b(size(a, 1), size(a, 1))
        real(rk) :: w(size(a, 1), 2 * size(a, 1)), row(2 * size(a, 1))
        integer :: n, i, p
        n = size(a, 1)
        w = 0.0_rk
        w(:, 1:n) = a
        do i = 1, n
            w(i, n + i) = 1.0_rk
        end do
        do i = 1, n
            p = i - 1 + maxloc(abs(w(i:, i)), 1)
            row = w(i, :)
            w(i, :) = w(p, :)
            w(p, :) = row
            w(i, :) = w(i, :) / w(i, i)
            do p = 1, n
                if (p /= i) w(p, :) = w(p, :) - w(p, i) * w(i, :)
            end do
        end do
        b = w(:, n + 1:)
    end function inverse

    !> Condensed unknown index of the 12 q of each element node (0 where held).
    pure function element_q_unknowns(this, e) result(dofs)
        type(ph_director_t), intent(in) :: this
        integer, intent(in) :: e
        integer :: dofs(12 * (this%degree + 1))
        integer :: a, node
        do a = 1, this%degree + 1
            node = (e - 1) * this%degree + a
            dofs(12 * (a - 1) + 1 : 12 * a) = this%node_unknown(1:12, node)
        end do
    end function element_q_unknowns

    !> Condensed pattern: element blocks couple all q of an element (momentum rows); the node
    !> blocks add the multiplier columns of the director rows and the constraint rows.
    subroutine build_condensed_pattern(this)
        type(ph_director_t), intent(inout) :: this
        type(csr_builder_t) :: builder
        integer :: dofs(12 * (this%degree + 1))
        logical :: nmask(18, 18)
        integer :: e, k, i, j, nq
        nq = 12 * (this%degree + 1)
        nmask = .false.
        ! A body's mass matrix couples all q of its node (through v = 2 (q - q_n)/h - v_n).
        if (size(this%bodies) > 0) nmask(1:12, 1:12) = .true.
        if (any(this%loads%follower .and. this%loads%node > 0)) nmask(1:3, 4:12) = .true.
        nmask(4:12, 4:12) = .true.
        nmask(4:12, 13:18) = .true.
        nmask(13:18, 4:12) = .true.
        call builder%init(this%n_condensed, this%n_elements * nq * nq + this%n_nodes * count(nmask))
        do e = 1, this%n_elements
            dofs = element_q_unknowns(this, e)
            call builder%add_block(dofs, dofs)
        end do
        do k = 1, this%n_nodes
            call builder%add_block(this%node_unknown(:, k), this%node_unknown(:, k), nmask)
        end do
        call builder%build(this%pattern)
        allocate(this%element_map(nq, nq, this%n_elements), source=0)
        do e = 1, this%n_elements
            dofs = element_q_unknowns(this, e)
            do j = 1, nq
                do i = 1, nq
                    if (dofs(i) > 0 .and. dofs(j) > 0) &
                        this%element_map(i, j, e) = this%pattern%position(dofs(i), dofs(j))
                end do
            end do
        end do
        allocate(this%node_map(18, 18, this%n_nodes), source=0)
        do k = 1, this%n_nodes
            do j = 1, 18
                do i = 1, 18
                    if (nmask(i, j) .and. this%node_unknown(i, k) > 0 .and. &
                        this%node_unknown(j, k) > 0) this%node_map(i, j, k) = &
                        this%pattern%position(this%node_unknown(i, k), this%node_unknown(j, k))
                end do
            end do
        end do
    end subroutine build_condensed_pattern

    !> The velocities v of every node zero (a quasistatic state holds the load steps' rates).
    subroutine ph_director_rest_state(this, x)
        class(ph_director_t), intent(in) :: this
        real(rk), intent(inout) :: x(:)
        integer :: i, k
        do k = 1, this%n_nodes
            do i = 13, 24
                if (this%node_dof(i, k) > 0) x(this%node_dof(i, k)) = 0.0_rk
            end do
        end do
    end subroutine ph_director_rest_state

    !> Newton starts from the last state with the positions and directors moved on by h v_n
    !> (q_{n+1} = q_n + h v_n, v_{n+1} = v_n: first order in h, where x_{n+1} = x_n is zeroth).
    subroutine ph_director_predictor(this, t_n, h, x_n, y)
        class(ph_director_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:)
        real(rk), intent(out) :: y(:)
        integer :: i, k
        if (.not. this%condensed) then
            y = x_n(1:this%n_dofs)
            ! An equilibrium solve starts from the last state itself: its velocities are those
            ! of the load steps, not of the continuation's pseudo-time.
            if (this%static) return
            do k = 1, this%n_nodes
                do i = 1, 12
                    if (this%node_dof(i, k) > 0 .and. this%node_dof(12 + i, k) > 0) &
                        y(this%node_dof(i, k)) = x_n(this%node_dof(i, k)) + h * x_n(this%node_dof(12 + i, k))
                end do
            end do
            return
        end if
        do k = 1, this%n_nodes
            do i = 1, 18
                if (this%node_unknown(i, k) > 0) y(this%node_unknown(i, k)) = &
                    x_n(this%node_dof(merge(i, 12 + i, i <= 12), k))
            end do
        end do
    end subroutine ph_director_predictor

    !> The state at t_{n+1}: the unknowns themselves, or with v and sigma recovered; and the
    !> driven nodes' velocities (driven_velocities).
    subroutine ph_director_update(this, t_n, h, x_n, y, x_1)
        class(ph_director_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: x_1(:)
        real(rk) :: times(2)
        integer :: k, e, i
        if (.not. this%condensed) then
            x_1(1:this%n_dofs) = y
            if (size(this%drives) == 0) return
            times = state_times(this, t_n, h)
            call this%unpack(x_n, this%q_n, this%v_n, this%lambda, this%s_n, times(1))
            call this%unpack(y, this%q_1, this%v_1, this%lambda, this%s_1, times(2))
            call driven_velocities(this, h)
            call store_driven_velocities()
            return
        end if
        call condensed_fields(this, t_n, h, x_n, y)
        call store_driven_velocities()
        do k = 1, this%n_nodes
            do i = 1, 12
                if (this%node_dof(i, k) > 0) x_1(this%node_dof(i, k)) = this%q_1(i, k)
                if (this%node_dof(12 + i, k) > 0) x_1(this%node_dof(12 + i, k)) = this%v_1(i, k)
            end do
            do i = 1, 6
                if (this%node_dof(24 + i, k) > 0) x_1(this%node_dof(24 + i, k)) = this%lambda(i, k)
            end do
        end do
        do e = 1, this%n_elements
            x_1(this%stress_dof(:, e)) = reshape(this%s_1(:, :, :, e), [n_stress(this)])
        end do
    contains
        subroutine store_driven_velocities()
            do k = 1, this%n_nodes
                if (this%drive_state(k) > 0) &
                    x_1(this%drive_state(k):this%drive_state(k) + 11) = this%v_1(:, k)
            end do
        end subroutine store_driven_velocities
    end subroutine ph_director_update

    !> q, lambda from the condensed unknowns (held q at t_n + h, held_q); v_{n+1} from R_K = 0
    !> and sigma_{n+1} from R_S = 0 (methods §5.5 items 1-2); the t_n fields from the state.
    !> A held coordinate keeps v = 0 (q_1 = q_n, v_n = 0); a driven node's v_{n+1} is the
    !> velocity the midpoint rule implies for its prescribed q.
    subroutine condensed_fields(this, t_n, h, x_n, y)
        type(ph_director_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk) :: r_e(this%n_local), zero(3), times(2)
        integer :: k, e, i, nodes(2), m, first
        times = state_times(this, t_n, h)
        call this%unpack(x_n, this%q_n, this%v_n, this%lambda, this%s_n, times(1))
        do k = 1, this%n_nodes
            this%q_1(:, k) = held_q(this, k, times(2))
            this%lambda(:, k) = 0.0_rk
            do i = 1, 12
                if (this%node_unknown(i, k) > 0) this%q_1(i, k) = y(this%node_unknown(i, k))
            end do
            do i = 1, 6
                if (this%node_unknown(12 + i, k) > 0) &
                    this%lambda(i, k) = y(this%node_unknown(12 + i, k))
            end do
            this%v_1(:, k) = 2.0_rk * (this%q_1(:, k) - this%q_n(:, k)) / h - this%v_n(:, k)
        end do
        m = 6 * this%degree
        first = 24 * (this%degree + 1) + 1
        zero = 0.0_rk
        do e = 1, this%n_elements
            nodes = this%element_nodes(e)
            ! R_S is linear in sigma_{n+1} with the matrix C_e: one correction from sigma_n.
            this%s_1(:, :, :, e) = this%s_n(:, :, :, e)
            call element_kernel(this, e, h, zero, zero, zero, [zero, zero], &
                ph_director_actuation_t(), r_e)
            this%s_1(:, :, 0, e) = this%s_n(:, :, 0, e) - reshape(matmul( &
                this%compliance_inverse(:, :, e), r_e(first:)), [6, this%degree])
        end do
    end subroutine condensed_fields

    !> The element kernel (methods §5.6 rows R_M, R_S) of element e on the workspace fields at
    !> t_n and t_{n+1}: its residual `r_e` and/or its Jacobian `j_e`, those present. nbar, mbar:
    !> the dead distributed loads, gravity the acceleration (times the element's line mass);
    !> follower: the follower ones' force and moment components in the director basis
    !> (rs_ph_director_follower).
    subroutine element_kernel(this, e, h, nbar, gravity, mbar, follower, actuation, r_e, j_e)
        type(ph_director_t), intent(in) :: this
        integer, intent(in) :: e
        real(rk), intent(in) :: h, nbar(3), gravity(3), mbar(3), follower(6)
        type(ph_director_actuation_t), intent(in) :: actuation
        real(rk), intent(out), contiguous, optional :: r_e(:)
        real(rk), intent(out), contiguous, optional :: j_e(:, :)
        real(rk) :: r_f(12, this%degree + 1), j_f(12, this%degree + 1, 12, this%degree + 1)
        integer :: nodes(2), a, b
        nodes = this%element_nodes(e)
        call ph_director_element_residual(this%basis, this%element_material(e), &
            this%element_length(e), this%eps_ref(:, :, e), h, this%static, this%q_n(:, nodes(1):nodes(2)), this%q_1(:, nodes(1):nodes(2)), &
            this%v_n(:, nodes(1):nodes(2)), this%v_1(:, nodes(1):nodes(2)), this%s_n(:, :, :, e), &
            this%s_1(:, :, :, e), nbar + this%element_line_mass(e) * gravity, mbar, actuation, &
            r_e, j_e)
        if (all(follower == 0.0_rk)) return
        ! The momentum (v) rows of node a are 24 (a - 1) + 13:24, the q columns of node b
        ! 24 (b - 1) + 1:12 (rs_ph_director_element's local layout).
        call ph_director_element_follower(this%basis, this%element_length(e), h, this%static, &
            this%q_n(:, nodes(1):nodes(2)), this%q_1(:, nodes(1):nodes(2)), follower(1:3), &
            follower(4:6), r_f, j_f)
        do a = 1, this%degree + 1
            if (present(r_e)) r_e(24 * a - 11:24 * a) = r_e(24 * a - 11:24 * a) + r_f(:, a)
            if (.not. present(j_e)) cycle
            do b = 1, this%degree + 1
                j_e(24 * a - 11:24 * a, 24 * b - 23:24 * b - 12) = &
                    j_e(24 * a - 11:24 * a, 24 * b - 23:24 * b - 12) + j_f(:, a, :, b)
            end do
        end do
    end subroutine element_kernel

    !> Residual (and, if `values` is present, the Schur-complement Jacobian) of the condensed
    !> step.
    subroutine condensed_step(this, t_n, h, x_n, y, f, values)
        type(ph_director_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out), optional :: f(:), values(:)
        real(rk) :: r_e(this%n_local), j_e(this%n_local, this%n_local)
        real(rk) :: schur(12 * (this%degree + 1), 12 * (this%degree + 1))
        real(rk) :: coupling(6 * this%degree, 12 * (this%degree + 1))
        real(rk) :: r_k(node_dofs), j_k(node_dofs, node_dofs)
        real(rk) :: nbar(3), mbar(3), gravity(3), follower(6), no_gravity(3), t_mid
        type(ph_director_actuation_t) :: actuation
        integer :: rows_m(12 * (this%degree + 1)), cols_q(12 * (this%degree + 1))
        integer :: cols_v(12 * (this%degree + 1))
        integer :: e, k, a, i, j, p, nodes(2), nq, first
        call condensed_fields(this, t_n, h, x_n, y)
        t_mid = load_time(this, t_n, h)
        call distributed_loads(this, t_mid, .false., nbar, mbar, gravity)
        call distributed_loads(this, t_mid, .true., follower(1:3), follower(4:6), no_gravity)
        actuation = actuation_at(this, t_mid)
        nq = 12 * (this%degree + 1)
        first = 24 * (this%degree + 1) + 1
        do a = 1, this%degree + 1
            do i = 1, 12
                cols_q(12 * (a - 1) + i) = 24 * (a - 1) + i
                cols_v(12 * (a - 1) + i) = 24 * (a - 1) + 12 + i
            end do
        end do
        rows_m = cols_v
        if (present(f)) f = 0.0_rk
        if (present(values)) values = 0.0_rk
        do e = 1, this%n_elements
            nodes = this%element_nodes(e)
            if (present(values)) then
                call element_kernel(this, e, h, nbar, gravity, mbar, follower, actuation, r_e, j_e)
                ! d/dq_{n+1} through v_{n+1} = 2 (q_{n+1} - q_n)/h - v_n, then the Schur
                ! complement of the stress block: A - B C_e^{-1} C.
                schur = j_e(rows_m, cols_q) + (2.0_rk / h) * j_e(rows_m, cols_v)
                coupling = j_e(first:, cols_q) + (2.0_rk / h) * j_e(first:, cols_v)
                schur = schur - matmul(j_e(rows_m, first:), &
                    matmul(this%compliance_inverse(:, :, e), coupling))
                do j = 1, nq
                    do i = 1, nq
                        p = this%element_map(i, j, e)
                        if (p > 0) values(p) = values(p) + schur(i, j)
                    end do
                end do
            else
                call element_kernel(this, e, h, nbar, gravity, mbar, follower, actuation, r_e)
            end if
            if (present(f)) then
                do a = 1, this%degree + 1
                    k = nodes(1) + a - 1
                    do i = 1, 12
                        if (this%node_unknown(i, k) > 0) f(this%node_unknown(i, k)) = &
                            f(this%node_unknown(i, k)) + r_e(24 * (a - 1) + 12 + i)
                    end do
                end do
            end if
        end do
        do k = 1, this%n_nodes
            if (all(this%node_unknown(:, k) == 0)) cycle
            if (present(values)) then
                call node_kernel(this, k, h, t_mid, r_k, j_k)
                ! Condensed row i is node row 12 + i (momentum 13:24, constraint 25:30); column
                ! j is q (1:12) or lambda (25:30). The node's momentum rows depend on v only
                ! through a body's mass: d/dq_{n+1} = 2/h d/dv_{n+1} there.
                do j = 1, 18
                    do i = 1, 18
                        p = this%node_map(i, j, k)
                        if (p > 0) values(p) = values(p) + j_k(12 + i, merge(j, 12 + j, j <= 12))
                    end do
                end do
                if (size(this%bodies) > 0) then
                    do j = 1, 12
                        do i = 1, 12
                            p = this%node_map(i, j, k)
                            if (p > 0) values(p) = values(p) + (2.0_rk / h) * j_k(12 + i, 12 + j)
                        end do
                    end do
                end if
            else
                call node_kernel(this, k, h, t_mid, r_k)
            end if
            if (present(f)) then
                do i = 1, 18
                    if (this%node_unknown(i, k) > 0) f(this%node_unknown(i, k)) = &
                        f(this%node_unknown(i, k)) + r_k(12 + i)
                end do
            end if
        end do
    end subroutine condensed_step

    !> H = kinetic + complementary energy of a state (methods §4.3 eq. 35).
    subroutine ph_director_energy(this, x, kinetic, strain)
        class(ph_director_t), intent(inout) :: this
        real(rk), intent(in) :: x(:)
        real(rk), intent(out) :: kinetic, strain
        integer :: e, nodes(2)
        call this%unpack(x, this%q_1, this%v_1, this%lambda, this%s_1)
        kinetic = 0.0_rk
        strain = 0.0_rk
        do e = 1, this%n_elements
            nodes = this%element_nodes(e)
            kinetic = kinetic + ph_director_element_kinetic_energy(this%basis, this%element_material(e), &
                this%element_length(e), this%v_1(:, nodes(1):nodes(2)))
            strain = strain + ph_director_element_complementary_energy(this%basis, &
                this%element_material(e), this%element_length(e), this%s_1(:, :, :, e))
        end do
        if (this%quasistatic) return
        do e = 1, size(this%bodies)
            kinetic = kinetic + ph_director_body_kinetic_energy(this%bodies(e), &
                this%v_1(:, this%bodies(e)%node))
        end do
    end subroutine ph_director_energy

    !> The energy terms of the accepted step: H_n and H_{n+1}, the work of the loads and of the
    !> actuators and the dissipation (Maxwell branches, Kelvin-Voigt stress and drags,
    !> docs/theory/ph_director.md "Damping"), whose balance H_{n+1} - H_n - W_n - W_act,n + D_n
    !> is the scheme's energy error (methods §5.3 item 1, §3.1, §9 item 7). The work includes
    !> that of the drives (drive_work), so the balance stays exact with driven ends. The endpoint
    !> equilibrium of a quasistatic run is not a time step: no terms, and its h is not a step of
    !> the grid.
    subroutine ph_director_accept_step(this, t_n, h, x_n, x_1, terms)
        class(ph_director_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), x_1(:)
        type(step_energy_t), intent(out) :: terms(:)
        real(rk) :: work, actuator_work, dissipated, nbar(3), mbar(3), gravity(3), force(3), &
            moment(3), t_mid
        real(rk) :: follower(6), d_mid(9), no_gravity(3)
        real(rk) :: kinetic_n, strain_n, kinetic_1, strain_1, weight(12), viscous, external
        type(ph_director_actuation_t) :: actuation
        integer :: e, k, i, nodes(2)
        logical :: carries, damped
        damped = any(this%material%viscosity > 0.0_rk) .or. this%material%drag > 0.0_rk .or. &
            this%material%angular_drag > 0.0_rk
        if (this%static) then
            terms(1) = step_energy_t(reported=.false., grid_step=.false.)
            return
        end if
        call this%energy(x_n, kinetic_n, strain_n)
        call this%energy(x_1, kinetic_1, strain_1)
        call this%unpack(x_n, this%q_n, this%v_n, this%lambda, this%s_n, t_n)
        call this%unpack(x_1, this%q_1, this%v_1, this%lambda, this%s_1, t_n + h)
        t_mid = t_n + 0.5_rk * h
        call distributed_loads(this, t_mid, .false., nbar, mbar, gravity)
        call distributed_loads(this, t_mid, .true., follower(1:3), follower(4:6), no_gravity)
        actuation = actuation_at(this, t_mid)
        work = 0.0_rk
        actuator_work = 0.0_rk
        dissipated = 0.0_rk
        do e = 1, this%n_elements
            nodes = this%element_nodes(e)
            associate (q_n => this%q_n(:, nodes(1):nodes(2)), q_1 => this%q_1(:, nodes(1):nodes(2)), &
                    v_n => this%v_n(:, nodes(1):nodes(2)), v_1 => this%v_1(:, nodes(1):nodes(2)))
                work = work + ph_director_element_external_work(this%basis, &
                    this%element_length(e), h, q_n, q_1, v_n, v_1, &
                    nbar + this%element_line_mass(e) * gravity, mbar)
                ! Follower loads: the work of the midpoint value the step applied
                ! (rs_ph_director_follower), so the balance stays exact.
                if (any(follower /= 0.0_rk)) work = work + ph_director_element_follower_work( &
                    this%basis, this%element_length(e), h, q_n, q_1, v_n, v_1, follower(1:3), &
                    follower(4:6))
                if (size(this%actuators) > 0) actuator_work = actuator_work + &
                    ph_director_element_actuator_work(this%basis, this%element_length(e), h, &
                    q_n, q_1, v_n, v_1, actuation)
                if (damped) then
                    call ph_director_element_damping_dissipation(this%basis, this%element_material(e), &
                        this%element_length(e), h, q_n, q_1, v_n, v_1, viscous, external)
                    dissipated = dissipated + viscous + external
                end if
            end associate
            if (this%material%n_branches > 0) dissipated = dissipated + &
                ph_director_element_dissipation(this%basis, this%element_material(e), &
                this%element_length(e), h, this%s_n(:, :, :, e), this%s_1(:, :, :, e))
        end do
        do k = 1, this%n_nodes
            ! A body's weight: its generalized force on the step of the node's coordinates.
            call body_forces(this, k, t_mid, weight, carries)
            if (carries) work = work + dot_product(weight, this%q_1(:, k) - this%q_n(:, k))
            call node_loads(this, k, t_mid, .false., force, moment)
            if (any(force /= 0.0_rk) .or. any(moment /= 0.0_rk)) work = work + &
                ph_director_node_external_work(h, this%q_n(:, k), this%q_1(:, k), &
                this%v_n(:, k), this%v_1(:, k), force, moment)
            ! A follower end load works as the dead load of its midpoint value.
            call node_loads(this, k, t_mid, .true., force, moment)
            if (all(force == 0.0_rk) .and. all(moment == 0.0_rk)) cycle
            d_mid = 0.5_rk * (this%q_n(4:12, k) + this%q_1(4:12, k))
            work = work + ph_director_node_external_work(h, this%q_n(:, k), this%q_1(:, k), &
                this%v_n(:, k), this%v_1(:, k), ph_director_follower_vector(d_mid, force), &
                ph_director_follower_vector(d_mid, moment))
        end do
        do i = 1, size(this%drives)
            work = work + drive_work(this, this%drives(i)%node, h, t_mid, nbar, gravity, mbar, &
                follower, actuation)
        end do
        terms(1) = step_energy_t(reported=.true., before=kinetic_n + strain_n, &
            after=kinetic_1 + strain_1, work=work, actuator_work=actuator_work, &
            dissipated=dissipated)
    end subroutine ph_director_accept_step

    !> The work of the drive on driven node k over the accepted step on the workspace fields
    !> (docs/theory/ph_director.md "Supports and loads"). The node's momentum rows R_M (the
    !> element rows of its velocities and its node loads, with no multipliers) are no equations
    !> of the step: their residual is h times the reaction f of the drive, h f = R_M, so the
    !> drive works W = h f . v_mid = R_M . v_mid. Testing every momentum row with v_mid (the
    !> energy proof of methods §5.3 item 1, with h v_mid = q_1 - q_n at the driven node too)
    !> gives H_{n+1} - H_n - W_loads - W_act + D = sum over the nodes of v_mid . R_M, which is
    !> this W up to the free rows' Newton residual.
    function drive_work(this, k, h, t_mid, nbar, gravity, mbar, follower, actuation) &
            result(work)
        type(ph_director_t), intent(in) :: this
        integer, intent(in) :: k
        real(rk), intent(in) :: h, t_mid, nbar(3), gravity(3), mbar(3), follower(6)
        type(ph_director_actuation_t), intent(in) :: actuation
        real(rk) :: work
        real(rk) :: r_e(this%n_local), r_k(node_dofs), reaction(12)
        integer :: e, a, nodes(2)
        reaction = 0.0_rk
        do e = 1, this%n_elements
            nodes = this%element_nodes(e)
            if (k < nodes(1) .or. k > nodes(2)) cycle
            call element_kernel(this, e, h, nbar, gravity, mbar, follower, actuation, r_e)
            a = k - nodes(1) + 1
            reaction = reaction + r_e(24 * a - 11:24 * a)
        end do
        call node_kernel(this, k, h, t_mid, r_k)
        reaction = reaction + r_k(13:24)
        work = dot_product(reaction, 0.5_rk * (this%v_n(:, k) + this%v_1(:, k)))
    end function drive_work

    !> The traits of a ph_director rod (the solver flags keep their defaults: the chain LU
    !> pivots the saddle point of the director constraints, Newton backtracks):
    !> - energy: the EM midpoint rule conserves energy up to the Newton tolerance (methods §5);
    !>   quasistatic runs book none;
    !> - quasistatic runs end with the endpoint equilibrium (DESIGN.md §3), solved as a
    !>   continuation (DESIGN.md §3, "Quasistatics"): the static rows (methods §2.8 eqs. 96e-g)
    !>   have the same unknowns as a step, so the Newton homotopy R(Y) - (1 - tau) R(x_from)
    !>   starts at x_from; quasistatic rods keep their stresses as unknowns (ph_director_init),
    !>   so Y has the layout of X; a condensed rod does not.
    pure function ph_director_traits(this) result(traits)
        class(ph_director_t), intent(in) :: this
        type(formulation_traits_t) :: traits
        traits%energy_scheme = merge(energy_unchecked, energy_consistent, this%quasistatic)
        traits%wants_endpoint_solve = this%quasistatic
        traits%continues_equilibrium = this%quasistatic .and. .not. this%condensed
        ! The implicit midpoint rule on (q, v, lambda, sigma) (methods §5.1-5.2).
        if (.not. this%quasistatic) traits%modal_form = modal_first_order
        ! The endpoint equilibrium of a quasistatic run (methods §2.8 eqs. 96e-g; no mass, its
        ! kinematic rows -h/2 (v_1 - v_n) keep the velocities out of the equilibrium): its
        ! Jacobian is the tangent stiffness of the mixed static problem.
        traits%static_tangent = this%quasistatic
    end function ph_director_traits

    !> Make the next steps the endpoint equilibrium at load time t_load (`endpoint`), or time
    !> steps: the kernels' `static` variant, methods §2.8 eqs. 96e-g with the reference strains.
    !> With continue_from (an uncondensed rod only), the equilibrium is the continuation
    !> anchored there: the static residual at continue_from, in the scaling of a step of
    !> length row_scale = 1. Back to time steps ends the continuation; an endpoint solve without
    !> continue_from leaves it as it was.
    subroutine ph_director_set_step_problem(this, endpoint, t_load, continue_from)
        class(ph_director_t), intent(inout) :: this
        logical, intent(in) :: endpoint
        real(rk), intent(in) :: t_load
        real(rk), intent(in), optional :: continue_from(:)
        this%static = endpoint
        this%t_static = t_load
        if (.not. endpoint) this%continuing = .false.
        if (.not. endpoint .or. .not. present(continue_from) .or. this%condensed) return
        this%row_scale = 1.0_rk
        if (allocated(this%anchor)) deallocate(this%anchor)
        allocate(this%anchor(this%n_dofs))
        call uncondensed_step(this, 0.0_rk, this%row_scale, continue_from, continue_from, &
            f=this%anchor)
        this%continuing = .true.
    end subroutine ph_director_set_step_problem

    !> No kinetic energy is reported (-1); with `from`, the largest rotation of a node's
    !> director triad from `from` to x: each director turns by 2 asin(|d_i,x - d_i,from| / 2)
    !> (unit directors, methods §2.1).
    function ph_director_state_measures(this, x, from) result(measures)
        class(ph_director_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        real(rk), intent(in), optional :: from(:)
        type(state_measures_t) :: measures
        real(rk) :: chord, angle
        integer :: k, i
        measures = state_measures_t()
        if (.not. present(from)) return
        angle = 0.0_rk
        do k = 1, this%n_nodes
            if (this%held(4, k)) cycle
            do i = 1, 3
                chord = norm2(x(this%node_dof(3 * i + 1:3 * i + 3, k)) - &
                    from(this%node_dof(3 * i + 1:3 * i + 3, k)))
                angle = max(angle, 2.0_rk * asin(min(1.0_rk, 0.5_rk * chord)))
            end do
        end do
        measures%largest_rotation = angle
    end function ph_director_state_measures

    !> The continuation's path weights (rod_formulation_t%path_weights): positions by 1 / L^2,
    !> directors by 1/2 (a small turn dtheta moves the three unit directors by |dd_1|^2 +
    !> |dd_2|^2 + |dd_3|^2 = 2 dtheta^2 for orthonormal directors, methods/ph_director_3d.md
    !> §2.1), each over the number of nodes; stresses, velocities and multipliers 0.
    subroutine ph_director_path_weights(this, w)
        class(ph_director_t), intent(in) :: this
        real(rk), intent(out) :: w(:)
        integer :: k
        w = 0.0_rk
        do k = 1, this%n_nodes
            where (this%node_dof(1:3, k) > 0) w(max(1, this%node_dof(1:3, k))) = &
                1.0_rk / (this%length**2 * this%n_nodes)
            where (this%node_dof(4:12, k) > 0) w(max(1, this%node_dof(4:12, k))) = &
                0.5_rk / this%n_nodes
        end do
    end subroutine ph_director_path_weights

    !> The node table of the rod (rod_nodes_t): q = (phi, d1, d2, d3) of node k is at
    !> node_dof(1:12, k) in X, and in Y at the same place or, condensed, at node_unknown(1:12,
    !> k); its generalized forces enter the momentum rows, the rows of v (node_dof(13:24, k))
    !> or, condensed, those of q (methods §5.5: the condensed rows of q are the momentum
    !> rows). A held coordinate has none: its q is held at the reference (a driven node's moves:
    !> held_moves, and it has no momentum rows).
    function ph_director_nodes(this) result(nodes)
        class(ph_director_t), intent(in) :: this
        type(rod_nodes_t) :: nodes
        integer :: k
        nodes%n_coordinates = 12
        nodes%directors_at = 4
        nodes%n_nodes = this%n_nodes
        nodes%n_elements = this%n_elements
        nodes%degree = this%degree
        nodes%n_gauss = this%basis%n_gauss
        allocate(nodes%element_length, source=this%element_length)
        allocate(nodes%state(12, this%n_nodes), nodes%unknown(12, this%n_nodes), &
            nodes%momentum(12, this%n_nodes), source=0)
        allocate(nodes%held, source=this%fixed_q)
        nodes%held_moves = size(this%drives) > 0
        do k = 1, this%n_nodes
            nodes%state(:, k) = this%node_dof(1:12, k)
            if (this%condensed) then
                nodes%unknown(:, k) = this%node_unknown(1:12, k)
                nodes%momentum(:, k) = this%node_unknown(1:12, k)
            else
                nodes%unknown(:, k) = this%node_dof(1:12, k)
                nodes%momentum(:, k) = merge(this%node_dof(13:24, k), 0, this%node_dof(1:12, k) > 0)
            end if
        end do
    end function ph_director_nodes

    !> A joint or plate tie in ph_director's nodal coordinates (rs_ph_director_node_tie).
    subroutine ph_director_new_tie(this, kind, q_a, q_b, axis, tie)
        class(ph_director_t), intent(in) :: this
        character(len=*), intent(in) :: kind
        real(rk), intent(in) :: q_a(:), q_b(:), axis(3)
        class(node_tie_t), allocatable, intent(out) :: tie
        call ph_director_node_tie(kind, q_a, q_b, axis, tie)
    end subroutine ph_director_new_tie

    subroutine ph_director_init_history(this, histories, capacity)
        class(ph_director_t), intent(in) :: this
        type(rod_history_t), intent(inout), target :: histories(:)
        integer, intent(in) :: capacity
        type(rod_history_t), pointer :: history
        integer :: e, b
        history => histories(1)
        call history%init(this%name, 'ph_director', this%n_nodes, this%n_elements * this%degree, &
            capacity, n_branches=this%material%n_branches)
        history%mesh = this%node_s
        do e = 1, this%n_elements
            do b = 1, this%degree
                history%stress_mesh((e - 1) * this%degree + b) = this%node_s((e - 1) * &
                    this%degree + 1) + 0.5_rk * this%element_length(e) * &
                    (1.0_rk + this%basis%stress_xi(b))
            end do
        end do
    end subroutine ph_director_init_history

    !> Append the state at time t: fields, energies, momenta, centre of mass and constraint
    !> residual (the system layer's ledger writes the sums since the previous record).
    subroutine ph_director_record(this, histories, t, x)
        class(ph_director_t), intent(inout) :: this
        type(rod_history_t), intent(inout), target :: histories(:)
        real(rk), intent(in) :: t, x(:)
        type(rod_history_t), pointer :: history
        real(rk) :: kinetic, strain, linear(3), angular(3), l_e(3), a_e(3), position(3), mass
        real(rk) :: weight, weighted_length
        real(rk) :: gamma(3, this%degree), kappa(3, this%degree)
        integer :: r, e, k, i, nodes(2), first, last, br
        history => histories(1)
        r = history%next_record()
        if (r == 0) return
        call this%energy(x, kinetic, strain)
        ! The fields of x at t in the t_{n+1} workspace (energy() placed driven nodes nowhere).
        call this%unpack(x, this%q_1, this%v_1, this%lambda, this%s_1, t)
        linear = 0.0_rk
        angular = 0.0_rk
        position = 0.0_rk
        weighted_length = 0.0_rk
        do e = 1, this%n_elements
            nodes = this%element_nodes(e)
            call ph_director_element_momenta(this%basis, this%element_material(e), this%element_length(e), &
                this%q_1(:, nodes(1):nodes(2)), this%v_1(:, nodes(1):nodes(2)), l_e, a_e)
            linear = linear + l_e
            angular = angular + a_e
            ! Weighted by the element's share of the line mass (&segment): the centre of mass.
            weight = 1.0_rk
            if (this%line_mass > 0.0_rk) weight = this%element_line_mass(e) / this%line_mass
            weighted_length = weighted_length + weight * this%element_length(e)
            position = position + weight * ph_director_element_position_integral(this%basis, &
                this%element_length(e), this%q_1(:, nodes(1):nodes(2)))
            call warn_if_coarse(this, e, t, this%q_1(10:12, nodes(1)), this%q_1(10:12, nodes(2)))
        end do
        history%time(r) = t
        history%kinetic(r) = kinetic
        history%strain(r) = strain
        history%total(r) = kinetic + strain
        history%center_of_mass(:, r) = position / weighted_length
        if (size(this%bodies) > 0) then
            ! The bodies on the ends: their momenta, and their mass in the centre of mass.
            position = this%line_mass * position
            mass = this%line_mass * weighted_length
            do e = 1, size(this%bodies)
                associate (body => this%bodies(e))
                    if (.not. this%quasistatic) then
                        call ph_director_body_momenta(body, this%q_1(:, body%node), &
                            this%v_1(:, body%node), l_e, a_e)
                        linear = linear + l_e
                        angular = angular + a_e
                    end if
                    position = position + body%mass * ph_director_body_centre(body, &
                        this%q_1(:, body%node))
                    mass = mass + body%mass
                end associate
            end do
            history%center_of_mass(:, r) = position / mass
        end if
        history%linear_momentum(:, r) = linear
        history%angular_momentum(:, r) = angular
        history%constraint_residual(r) = 0.0_rk
        do k = 1, this%n_nodes
            history%position(:, k, r) = this%q_1(1:3, k)
            history%velocity(:, k, r) = this%v_1(1:3, k)
            do i = 1, 3
                history%directors(:, i, k, r) = this%q_1(3 * i + 1 : 3 * i + 3, k)
                history%director_velocity(:, i, k, r) = this%v_1(3 * i + 1 : 3 * i + 3, k)
            end do
            history%constraint_residual(r) = max(history%constraint_residual(r), &
                maxval(abs(ph_director_node_constraint(this%q_1(:, k)))))
        end do
        do e = 1, this%n_elements
            first = (e - 1) * this%degree + 1
            last = e * this%degree
            ! The total stress is the sum of the branches (methods §3.1 eq. 49).
            history%stress(:, first:last, r) = sum(this%s_1(:, :, :, e), dim=3)
            do br = 1, this%material%n_branches
                history%branch_stress(:, first:last, br, r) = this%s_1(:, :, br, e)
            end do
            nodes = this%element_nodes(e)
            call ph_director_element_strains(this%basis, this%element_length(e), &
                this%q_1(:, nodes(1):nodes(2)), gamma, kappa)
            history%strains(1:3, first:last, r) = gamma
            history%strains(4:6, first:last, r) = kappa
        end do
    end subroutine ph_director_record

    !> Once per rod: the directors are interpolated by Lagrange polynomials, so when the end
    !> directors of an element are more than 90 degrees apart the interpolated directors shrink
    !> towards zero inside it and the strains measured with them lose the element's stretch and
    !> shear (a zero-energy mode; on the planar spaghetti's step load with p = 1 the loaded end
    !> element stretched 30-fold). The mesh is too coarse for the rotation there.
    subroutine warn_if_coarse(this, e, t, d3_first, d3_last)
        type(ph_director_t), intent(inout) :: this
        integer, intent(in) :: e
        real(rk), intent(in) :: t, d3_first(3), d3_last(3)
        if (this%warned_coarse .or. dot_product(d3_first, d3_last) >= 0.0_rk) return
        this%warned_coarse = .true.
        call log_warning('rod ''' // this%name // ''': at t = ' // str(t) // ' the end directors ' // &
            'd3 of element ' // str(e) // ' are more than 90 degrees apart; the interpolated ' // &
            'directors degenerate inside it (docs/theory/ph_director.md): refine the mesh or ' // &
            'raise the degree')
    end subroutine warn_if_coarse

    function ph_director_describe(this) result(text)
        class(ph_director_t), intent(in) :: this
        character(len=:), allocatable :: text
        text = 'rod ''' // this%name // ''': ph_director, ' // str(this%n_elements) // &
            ' elements of degree ' // str(this%degree) // ', ' // str(this%basis%n_gauss) // &
            ' Gauss points, ' // str(this%n_unknown()) // ' Newton unknowns (' // &
            trim(merge('stresses condensed', 'uncondensed       ', this%condensed)) // '), ' // &
            str(this%pattern%nnz()) // ' Jacobian non-zeros'
    end function ph_director_describe

end module rs_ph_director
