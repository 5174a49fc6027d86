#include "rs_macros.h"
!> Viscoelastic rods as special Euclidean strands on a staggered grid (seed 004, methods/
!> se3_strands.md): the only unknowns are the intrinsic fields P (momentum, at the nodes) and
!> Sigma (stress, at the segment midpoints and two ghost segments), advanced by the paper's
!> semi-implicit scheme (eqs. 11-15, methods §3.5): the nonlinear ad coefficients frozen at t_n,
!> every linear term at t_{n+1}, so a step is ONE sparse linear solve and no Newton loop. The
!> placement is not an unknown: it is rebuilt from the strains by the closed-form SE(3)
!> exponential, marched in space from the section at s = 0 (Appendix A, methods §3.6).
!>
!> Conventions: rs_se3_strand_kernels (order (3, 1, 2), paper signs of the angular parts).
!>
!> Unknowns, interleaved so that the matrix is block tridiagonal with 6 x 6 blocks (half
!> bandwidth 11 against the paper's 23, methods §3.5): block 0 is the ghost Sigma_{-1,0},
!> block 2k+1 is P_k (k = 0..N), block 2k+2 is Sigma_{k,k+1} (k = 0..N; N is the ghost
!> Sigma_{N,N+1}). The state X is these unknowns followed by the pose of the section at s = 0
!> (x_0, then the 3 x 3 matrix A_0 = [d3 d1 d2]), which moves only at a driven end.
!>
!> Additions to the paper (docs/theory/se3_strand.md):
!> - the free end's half cell takes the ad^T term of its one physical segment in full, not the
!>   paper's average with the ghost segment (an end moment of about h |f| / 2 that created
!>   energy, issue 21 item 12);
!> - dead loads (end and distributed, gravity) with their rotation linearized implicitly,
!>   f_{n+1} = f_n + dt w_{n+1} x f_n (methods §7 item 3: the paper's explicit lag diverges on
!>   the 600 N bend);
!> - a Kelvin-Voigt viscous stress Sigma_v = tau A dU/dt = tau dSigma/dt in the divergence and
!>   the ad^T term of eq. (11), next to the paper's internal law -D_in dU/dt (a body force that
!>   need not dissipate, methods §2.6);
!> - a driven end by prescribed spatial velocity and angular velocity (P_0 = M V_0, eq. 13),
!>   its pose advanced by the exponential of the prescribed twist.
!> - rods that vary along their length (&segment, issue 26 item 5): A per segment, M per node
!>   as the half-cell-weighted mean of its two segments' (docs/theory/se3_strand.md).
module rs_se3_strand
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: str
    use rs_model_scene, only: scene_t, rod_input_t, load_applies_to, element_properties, &
        axial_reference
    use rs_model_rod_history, only: rod_history_t
    use rs_model_time_function, only: time_function_t, time_function_from_load, time_function_from_bc
    use rs_model_rod_geometry, only: rod_geometry_t, rod_geometry_of, centreline_point, &
        centreline_frame
    use rs_math_so3, only: exp_so3, hat
    use rs_math_se3, only: log_se3, pose_relative
    use rs_assembly_csr_pattern, only: csr_builder_t, csr_pattern_t
    use rs_formulations_formulation, only: rod_formulation_t, formulation_traits_t, state_valid, &
        state_invalid, state_measures_t, modal_one_step
    use rs_formulations_energy_sentinel, only: step_energy_t, energy_dissipative
    use rs_se3_strand_kernels, only: cross_matrix, strand_march, strand_ad_transpose_block, &
        strand_ad_block, strand_ad_times, strand_cross, strand_row_residual, strand_row_to_csr, &
        strand_row_has_nan
    implicit none
    private

    !> An end load (at s = L) or a distributed load, scaled by a time function. Dead loads in
    !> inertial components; follower loads in K components (F3, F1, F2) of the given director
    !> components.
    type :: strand_load_t
        logical :: at_end = .false.
        logical :: follower = .false.
        real(rk) :: force(3) = 0.0_rk
        real(rk) :: moment(3) = 0.0_rk
        !> Gravity: force is the acceleration, times each node's rhoA.
        logical :: per_mass = .false.
        type(time_function_t) :: factor
    end type strand_load_t

    !> One driven-end motion: spatial velocity f(t) velocity and angular velocity
    !> f(t) angular_velocity of the section at s = 0 (several add up).
    type :: strand_drive_t
        real(rk) :: velocity(3) = 0.0_rk
        real(rk) :: angular_velocity(3) = 0.0_rk
        type(time_function_t) :: factor
    end type strand_drive_t

    type, extends(rod_formulation_t), public :: se3_strand_t
        character(len=:), allocatable :: name
        !> N segments, N + 1 nodes; blocks 0 .. 2N + 2.
        integer :: n_seg = 0, n_blocks = 0
        real(rk) :: length = 0.0_rk
        !> Segment lengths h_k (k = 0..N, the ghost N repeating N - 1), the nodal dual cells
        !> (s_{k+1} - s_{k-1}) / 2 of eq. (11) (k = 1..N, with the ghost node s_{N+1}), and the
        !> nodal weights of the energy (trapezoidal: h/2 at both ends).
        real(rk), allocatable :: seg_h(:), dual(:), weight(:)
        !> Diagonal inertia M = (rhoI1 + rhoI2, rhoI1, rhoI2, rhoA, rhoA, rhoA) per node
        !> (0..N) and stiffness A = (GJ, EI1, EI2, EA, GA1, GA2) per segment (-1..N, the ghosts
        !> copy their neighbours) (paper eq. 3), and their inverses. With &segment (issue 26
        !> item 5) A is the segment's and a node's M the half-cell-weighted mean
        !> (h_- M_- + h_+ M_+) / (h_- + h_+) of its two segments', which keeps the total mass.
        real(rk), allocatable :: mass(:, :), mass_inv(:, :)
        real(rk), allocatable :: stiff(:, :), stiff_inv(:, :)
        !> Relaxed strains per segment, -1..N (ghosts repeat their neighbours).
        real(rk), allocatable :: u_bar(:, :)
        real(rk) :: eta_internal = 0.0_rk
        !> The external drag D_ex per body velocity component (angular_drag on the three
        !> angular rows, drag on the three linear ones, each plus the paper's scalar
        !> external_damping) and the Kelvin-Voigt times per stress component, both in the
        !> order of V and Sigma (paper eq. 3).
        real(rk) :: eta_external(6) = 0.0_rk, tau_kv(6) = 0.0_rk
        !> &rod free_end = 'paper': seed 004's ghost-averaged free end instead of the balanced one.
        logical :: paper_free_end = .false.
        !> The start s = 0 is free (no &bc there, issue 26 item 4): its stress is zero and its
        !> momentum obeys the half-cell balance, as the free end's (docs/theory/se3_strand.md,
        !> "A free start"); otherwise P_0 is prescribed (clamped or driven, methods §3.4).
        logical :: free_start = .false.
        type(strand_drive_t), allocatable :: drives(:)
        type(strand_load_t), allocatable :: loads(:)
        !> Loads need the placement at t_n (dead directions); false: no reconstruction per step.
        logical :: needs_pose = .false.
        real(rk), allocatable :: initial(:)
        type(csr_pattern_t) :: pattern
        !> Column blocks of each block row (0-based, -1 = none) and the CSR position of entry
        !> (i, j) of block c of row b.
        integer, allocatable :: row_blocks(:, :), block_map(:, :, :, :)
        !> True if the CSR values are the block rows in order, each row of a block row its blocks
        !> side by side (block_map(i, j, c, b) counts up in the order b, i, c, j) and the blocks
        !> present in a row are its first n_row_blocks(b): the Jacobian is then copied block row
        !> by block row without block_map.
        logical :: csr_in_block_order = .false.
        integer, allocatable :: n_row_blocks(:)
        ! The linear system of the current step, A Y = b, cached for the residual, the Jacobian
        ! and the accepted step (valid for (t_n, h, x_n) = key_*).
        real(rk), allocatable :: blocks(:, :, :, :), rhs(:, :)
        logical :: cached = .false.
        real(rk) :: key_t = 0.0_rk, key_h = 0.0_rk
        real(rk), allocatable :: key_x(:)
        ! Workspace (no allocation in the time loop): placement at t_n and t_{n+1}, end-load
        ! and distributed-load vectors at t_{n+1} in K components, the dead ones (load_f,
        ! load_m: turned with the section, linearized) and the follower ones apart.
        real(rk), allocatable :: pose_a(:, :, :), pose_x(:, :)
        real(rk), allocatable :: load_f(:, :), load_m(:, :)
        real(rk), allocatable :: load_f_follower(:, :), load_m_follower(:, :)
        real(rk) :: end_f(3) = 0.0_rk, end_m(3) = 0.0_rk
        real(rk) :: end_f_follower(3) = 0.0_rk, end_m_follower(3) = 0.0_rk
    contains
        procedure :: init => strand_init
        procedure :: n_state => strand_n_state
        procedure :: n_unknown => strand_n_unknown
        procedure :: jacobian_pattern => strand_jacobian_pattern
        procedure :: initial_state => strand_initial_state
        procedure :: predictor => strand_predictor
        procedure :: update => strand_update
        procedure :: step_residual => strand_step_residual
        procedure :: step_jacobian => strand_step_jacobian
        procedure :: state_jacobian => strand_state_jacobian
        procedure :: accept_step => strand_accept_step
        procedure :: init_history => strand_init_history
        procedure :: record => strand_record
        procedure :: describe => strand_describe
        procedure :: traits => strand_traits
        procedure :: state_measures => strand_state_measures
        procedure, private :: assemble, ensure_assembled, march_poses, drive_twist, end_loads
        procedure, private :: distributed_loads, energies
    end type se3_strand_t

contains

    ! ---- Building the rod ---------------------------------------------------------------------

    subroutine strand_init(this, scene, rods, err)
        class(se3_strand_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:)
        type(error_t), allocatable, intent(out) :: err
        integer :: n
        if (size(rods) /= 1) then
            RS_SET_ERROR(err, 'se3_strand%init', 'se3_strand rods cannot be joined')
            return
        end if
        associate (rod => scene%rods(rods(1)))
            this%name = trim(rod%name)
            this%n_seg = rod%n_elements
            n = this%n_seg
            this%n_blocks = 2 * n + 3
            this%length = rod%length
            call build_properties(this, element_properties(scene, rod, n), err)
            RS_RETURN_IF_ERROR(err)
            this%eta_external = rod%external_damping + [spread(rod%angular_drag, 1, 3), &
                spread(rod%drag, 1, 3)]
            this%eta_internal = rod%internal_damping
            ! &rod kelvin_voigt_time is in the order (EA, GA1, GA2, EI1, EI2, GJ).
            this%tau_kv = rod%kelvin_voigt_time([6, 4, 5, 1, 2, 3])
            this%paper_free_end = trim(rod%free_end) == 'paper'
            allocate(this%initial(this%n_state()), source=0.0_rk)
            call read_supports(this, scene, err)
            RS_RETURN_IF_ERROR(err)
            call reference_configuration(this, rod)
            call read_loads(this, scene, err)
            RS_RETURN_IF_ERROR(err)
        end associate
        call build_pattern(this)
        allocate(this%blocks(6, 6, 3, 0:this%n_blocks - 1), this%rhs(6, 0:this%n_blocks - 1), &
            source=0.0_rk)
        allocate(this%key_x(this%n_state()), source=0.0_rk)
        allocate(this%pose_a(3, 3, 0:n), this%pose_x(3, 0:n), this%load_f(3, 0:n), &
            this%load_m(3, 0:n), this%load_f_follower(3, 0:n), this%load_m_follower(3, 0:n), &
            source=0.0_rk)
    end subroutine strand_init

    !> Uniform segments (lengths, dual cells, nodal weights) and their properties: `properties`
    !> (rs_model_scene element_properties: EA, GA1, GA2, EI1, EI2, GJ, rhoA, rhoI1, rhoI2 per
    !> segment) give each segment its stiffness A and each node the half-cell-weighted mean of
    !> its segments' inertias M (docs/theory/se3_strand.md, "Rods that vary along their length").
    subroutine build_properties(this, properties, err)
        type(se3_strand_t), intent(inout) :: this
        real(rk), intent(in) :: properties(:, :)
        type(error_t), allocatable, intent(out) :: err
        real(rk) :: seg_mass(6, 0:this%n_seg - 1), h
        integer :: k, n
        n = this%n_seg
        h = this%length / real(n, rk)
        allocate(this%seg_h(0:n), this%dual(0:n), this%weight(0:n))
        this%seg_h = h
        this%dual = h
        this%weight = h
        this%weight(0) = 0.5_rk * h
        this%weight(n) = 0.5_rk * h
        allocate(this%mass(6, 0:n), this%mass_inv(6, 0:n), this%stiff(6, -1:n), &
            this%stiff_inv(6, -1:n))
        do k = 0, n - 1
            this%stiff(:, k) = properties([6, 4, 5, 1, 2, 3], k + 1)
            seg_mass(:, k) = [properties(8, k + 1) + properties(9, k + 1), properties(8, k + 1), &
                properties(9, k + 1), spread(properties(7, k + 1), 1, 3)]
        end do
        this%stiff(:, -1) = this%stiff(:, 0)
        this%stiff(:, n) = this%stiff(:, n - 1)
        this%mass(:, 0) = seg_mass(:, 0)
        this%mass(:, n) = seg_mass(:, n - 1)
        do k = 1, n - 1
            this%mass(:, k) = (this%seg_h(k - 1) * seg_mass(:, k - 1) + this%seg_h(k) * &
                seg_mass(:, k)) / (this%seg_h(k - 1) + this%seg_h(k))
        end do
        if (any(this%mass <= 0.0_rk) .or. any(this%stiff <= 0.0_rk)) then
            RS_SET_ERROR(err, 'se3_strand%init', 'rod ''' // this%name // ''': se3_strand needs positive inertia and stiffness in all six components')
            return
        end if
        this%mass_inv = 1.0_rk / this%mass
        this%stiff_inv = 1.0_rk / this%stiff
    end subroutine build_properties

    !> The relaxed strains are the discrete strains of the initial placement
    !> (the SE(3) logarithm of the relative pose of neighbouring nodes, exact for a straight rod,
    !> a circle or a helix with its frame), or those of the straight rod if `prestressed` (the
    !> rod starts with the stresses of its initial shape); a prestrained rod's translational
    !> ones divided by 1 + prestrain (docs/theory/prestretched_starts.md). Initial state:
    !> P = M V of the rigid velocity field, Sigma = A (U_0 - U_bar), ghosts mirrored so that eqs. (14)-(15) hold with
    !> no end stress.
    subroutine reference_configuration(this, rod)
        type(se3_strand_t), intent(inout) :: this
        type(rod_input_t), intent(in) :: rod
        type(rod_geometry_t) :: geometry
        real(rk) :: d(3, 3), a(3, 3, 0:this%n_seg), x(3, 0:this%n_seg), a_rel(3, 3), r_rel(3)
        real(rk) :: theta(6), u0(6, -1:this%n_seg), v(3), omega(3), vk(6), h
        integer :: k, n
        n = this%n_seg
        h = rod%length / real(n, rk)
        allocate(this%u_bar(6, -1:n))
        geometry = rod_geometry_of(rod)
        do k = 0, n
            d = centreline_frame(geometry, h * real(k, rk))
            x(:, k) = centreline_point(geometry, h * real(k, rk))
            a(:, 1, k) = d(:, 3)
            a(:, 2, k) = d(:, 1)
            a(:, 3, k) = d(:, 2)
        end do
        do k = 0, n - 1
            call pose_relative(a(:, :, k), x(:, k), a(:, :, k + 1), x(:, k + 1), a_rel, r_rel)
            theta = log_se3(a_rel, r_rel) / h
            ! Standard twist (sigma, kappa) -> paper strain (-kappa, sigma).
            u0(:, k) = [-theta(4:6), theta(1:3)]
        end do
        u0(:, -1) = u0(:, 0)
        u0(:, n) = u0(:, n - 1)
        if (rod%prestressed) then
            do k = -1, n
                this%u_bar(:, k) = [0.0_rk, 0.0_rk, 0.0_rk, 1.0_rk, 0.0_rk, 0.0_rk]
            end do
        else
            this%u_bar = u0
        end if
        this%u_bar(4:6, :) = axial_reference(rod) * this%u_bar(4:6, :)
        ! Stresses: segments 0..N-1, the ghost at 0 copies segment 0 (eq. 14) or, at a free
        ! start, mirrors it (no start stress), the ghost at N mirrors N-1 (eq. 15 with no end
        ! load).
        do k = 0, n - 1
            this%initial(s_index(k) + 1:s_index(k) + 6) = this%stiff(:, k) * (u0(:, k) - &
                this%u_bar(:, k))
        end do
        this%initial(s_index(-1) + 1:s_index(-1) + 6) = this%initial(s_index(0) + 1:s_index(0) + 6)
        if (this%free_start) this%initial(s_index(-1) + 1:s_index(-1) + 6) = &
            -this%initial(s_index(-1) + 1:s_index(-1) + 6)
        this%initial(s_index(n) + 1:s_index(n) + 6) = -this%initial(s_index(n - 1) + 1:s_index(n - 1) + 6)
        ! Momenta of the rigid velocity field v = velocity + omega x (x - c): body v_K = A^T v,
        ! paper angular part w = -A^T omega.
        omega = rod%angular_velocity
        do k = 0, n
            v = rod%velocity + matmul(hat(omega), x(:, k) - rod%rotation_center)
            vk(1:3) = -matmul(transpose(a(:, :, k)), omega)
            vk(4:6) = matmul(transpose(a(:, :, k)), v)
            this%initial(p_index(k) + 1:p_index(k) + 6) = this%mass(:, k) * vk
        end do
        ! Pose of the section at s = 0.
        this%initial(pose_index(this) + 1:pose_index(this) + 3) = x(:, 0)
        this%initial(pose_index(this) + 4:pose_index(this) + 12) = reshape(a(:, :, 0), [9])
    end subroutine reference_configuration

    !> The start is clamped (P_0 = 0), driven (P_0 = M V_0(t)) or free (no &bc, or kind
    !> 'free'); the end is free (stress prescribed by the end loads). --check-input has refused
    !> anything else (capability row).
    subroutine read_supports(this, scene, err)
        type(se3_strand_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        type(error_t), allocatable, intent(out) :: err
        type(strand_drive_t) :: drive
        character(len=:), allocatable :: message
        integer :: i
        allocate(this%drives(0))
        this%free_start = .true.
        do i = 1, size(scene%bcs)
            associate (bc => scene%bcs(i))
                if (trim(bc%rod) /= this%name) cycle
                if (trim(bc%end) == 'end' .and. trim(bc%kind) /= 'free') then
                    message = 'rod ''' // this%name // ''': se3_strand prescribes the stress at ' // &
                        's = L (methods/se3_strands.md §3.4); a ''' // trim(bc%kind) // &
                        ''' end ''end'' is not available'
                    RS_SET_ERROR(err, 'se3_strand%init', message)
                    return
                end if
                if (trim(bc%end) /= 'start') cycle
                select case (trim(bc%kind))
                case ('free')
                case ('clamped')
                    this%free_start = .false.
                case ('driven')
                    this%free_start = .false.
                    drive = strand_drive_t()
                    call time_function_from_bc(bc, drive%factor, err)
                    RS_RETURN_IF_ERROR(err)
                    drive%velocity = bc%velocity
                    drive%angular_velocity = bc%angular_velocity
                    this%drives = [this%drives, drive]
                case default
                    message = 'rod ''' // this%name // ''': the start of an se3_strand rod is ' // &
                        'clamped, driven or free (methods/se3_strands.md §3.4)'
                    RS_SET_ERROR(err, 'se3_strand%init', message)
                    return
                end select
            end associate
        end do
    end subroutine read_supports

    !> End loads at s = L (eq. 15), distributed loads and gravity (F of eq. 11).
    subroutine read_loads(this, scene, err)
        type(se3_strand_t), intent(inout) :: this
        type(scene_t), intent(in) :: scene
        type(error_t), allocatable, intent(out) :: err
        type(strand_load_t) :: load
        character(len=:), allocatable :: message
        integer :: i, n
        allocate(this%loads(size(scene%loads)))
        n = 0
        do i = 1, size(scene%loads)
            associate (input => scene%loads(i))
                if (.not. load_applies_to(input, this%name)) cycle
                load = strand_load_t()
                call time_function_from_load(input, load%factor, err)
                RS_RETURN_IF_ERROR(err)
                load%follower = trim(input%frame) == 'follower'
                select case (trim(input%where))
                case ('end')
                    load%at_end = .true.
                case ('distributed', 'gravity')
                    load%at_end = .false.
                case default
                    message = 'rod ''' // this%name // ''': se3_strand takes loads at the end, ' // &
                        'distributed loads and gravity (none at the start)'
                    RS_SET_ERROR(err, 'se3_strand%init', message)
                    return
                end select
                if (trim(input%where) == 'gravity') then
                    load%force = input%acceleration
                    load%per_mass = .true.
                else if (load%follower) then
                    load%force = [input%force(3), input%force(1), input%force(2)]
                    load%moment = [input%moment(3), input%moment(1), input%moment(2)]
                else
                    load%force = input%force
                    load%moment = input%moment
                end if
                if (.not. load%follower) this%needs_pose = .true.
                n = n + 1
                this%loads(n) = load
            end associate
        end do
        this%loads = this%loads(1:n)
    end subroutine read_loads

    !> Block rows: ghost row 0 {0, 2} (eq. 14); P_0 {1} (eq. 13), or node 0 {0, 1, 2} at a free
    !> start; node k {2k, 2k+1, 2k+2}
    !> (eq. 11); segment k {2k+1, 2k+2, 2k+3} (eq. 12); the end ghost {2N, 2N+1, 2N+2} (eq. 15).
    !> Full 6 x 6 blocks.
    subroutine build_pattern(this)
        type(se3_strand_t), intent(inout) :: this
        type(csr_builder_t) :: builder
        integer :: b, c, i, j, rows(6), cols(6), nb, at
        nb = this%n_blocks
        allocate(this%row_blocks(3, 0:nb - 1), source=-1)
        this%row_blocks(1:2, 0) = [0, 2]
        this%row_blocks(1, 1) = 1
        if (this%free_start) this%row_blocks(:, 1) = [0, 1, 2]
        do b = 2, nb - 1
            this%row_blocks(:, b) = [b - 1, b, b + 1]
        end do
        this%row_blocks(:, nb - 1) = [nb - 3, nb - 2, nb - 1]
        call builder%init(6 * nb, 108 * nb)
        do b = 0, nb - 1
            rows = [(6 * b + i, i = 1, 6)]
            do c = 1, 3
                if (this%row_blocks(c, b) < 0) cycle
                cols = [(6 * this%row_blocks(c, b) + i, i = 1, 6)]
                call builder%add_block(rows, cols)
            end do
        end do
        call builder%build(this%pattern)
        allocate(this%block_map(6, 6, 3, 0:nb - 1), source=0)
        do b = 0, nb - 1
            do c = 1, 3
                if (this%row_blocks(c, b) < 0) cycle
                do j = 1, 6
                    do i = 1, 6
                        this%block_map(i, j, c, b) = this%pattern%position(6 * b + i, &
                            6 * this%row_blocks(c, b) + j)
                    end do
                end do
            end do
        end do
        ! Checked, not assumed: the order depends on the pattern's sorting of each row.
        allocate(this%n_row_blocks(0:nb - 1))
        this%csr_in_block_order = .true.
        at = 0
        do b = 0, nb - 1
            this%n_row_blocks(b) = count(this%row_blocks(:, b) >= 0)
            if (any(this%row_blocks(1:this%n_row_blocks(b), b) < 0)) &
                this%csr_in_block_order = .false.
            do i = 1, 6
                do c = 1, 3
                    if (this%row_blocks(c, b) < 0) cycle
                    do j = 1, 6
                        at = at + 1
                        if (this%block_map(i, j, c, b) /= at) this%csr_in_block_order = .false.
                    end do
                end do
            end do
        end do
        if (at /= this%pattern%nnz()) this%csr_in_block_order = .false.
    end subroutine build_pattern

    ! ---- Indices ------------------------------------------------------------------------------

    !> Offset of P_k and of Sigma_{k,k+1} (k = -1..N) in Y and X.
    pure integer function p_index(k)
        integer, intent(in) :: k
        p_index = 6 * (2 * k + 1)
    end function p_index

    pure integer function s_index(k)
        integer, intent(in) :: k
        s_index = 6 * (2 * k + 2)
    end function s_index

    pure integer function pose_index(this)
        type(se3_strand_t), intent(in) :: this
        pose_index = 6 * this%n_blocks
    end function pose_index

    pure function p_at(x, k) result(p)
        real(rk), intent(in) :: x(:)
        integer, intent(in) :: k
        real(rk) :: p(6)
        p = x(p_index(k) + 1:p_index(k) + 6)
    end function p_at

    pure function s_at(x, k) result(s)
        real(rk), intent(in) :: x(:)
        integer, intent(in) :: k
        real(rk) :: s(6)
        s = x(s_index(k) + 1:s_index(k) + 6)
    end function s_at

    ! ---- Sizes, state, predictor, update ----------------------------------------------------

    pure integer function strand_n_state(this)
        class(se3_strand_t), intent(in) :: this
        strand_n_state = 6 * this%n_blocks + 12
    end function strand_n_state

    pure integer function strand_n_unknown(this)
        class(se3_strand_t), intent(in) :: this
        strand_n_unknown = 6 * this%n_blocks
    end function strand_n_unknown

    subroutine strand_jacobian_pattern(this, row_ptr, cols)
        class(se3_strand_t), intent(in) :: this
        integer, allocatable, intent(out) :: row_ptr(:), cols(:)
        call this%pattern%zero_based(row_ptr, cols)
    end subroutine strand_jacobian_pattern

    subroutine strand_initial_state(this, x)
        class(se3_strand_t), intent(in) :: this
        real(rk), intent(out) :: x(:)
        x = this%initial
    end subroutine strand_initial_state

    !> Y = X_n's unknowns (the step is linear: any start gives the same solve).
    subroutine strand_predictor(this, t_n, h, x_n, y)
        class(se3_strand_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:)
        real(rk), intent(out) :: y(:)
        y = x_n(1:size(y))
    end subroutine strand_predictor

    !> X_{n+1}: the unknowns, and the pose at s = 0 moved over the step by the twist at t_{n+1}
    !> (x_0 + h v, Exp(h omega) A_0; exact for a constant twist): the prescribed one, or at a
    !> free start the section's own V_0 = M^-1 P_0 of the step (body components, the paper's
    !> sign: omega = -A_0 w, which is the same with A_0 at t_n or t_{n+1} since the section
    !> turns about it, and v = A_0(t_{n+1}) v_K, as a drive's V_0 is taken).
    subroutine strand_update(this, t_n, h, x_n, y, x_1)
        class(se3_strand_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: x_1(:)
        real(rk) :: v(3), omega(3), a0(3, 3), v0(6)
        integer :: at
        at = pose_index(this)
        x_1(1:at) = y
        a0 = reshape(x_n(at + 4:at + 12), [3, 3])
        if (this%free_start) then
            v0 = this%mass_inv(:, 0) * p_at(y, 0)
            omega = -matmul(a0, v0(1:3))
            a0 = matmul(exp_so3(h * omega), a0)
            v = matmul(a0, v0(4:6))
        else
            call this%drive_twist(t_n + h, v, omega)
            a0 = matmul(exp_so3(h * omega), a0)
        end if
        x_1(at + 1:at + 3) = x_n(at + 1:at + 3) + h * v
        x_1(at + 4:at + 12) = reshape(a0, [9])
    end subroutine strand_update

    !> The spatial velocity and angular velocity of the section at s = 0 at time t.
    subroutine drive_twist(this, t, v, omega)
        class(se3_strand_t), intent(in) :: this
        real(rk), intent(in) :: t
        real(rk), intent(out) :: v(3), omega(3)
        real(rk) :: f
        integer :: i
        v = 0.0_rk
        omega = 0.0_rk
        do i = 1, size(this%drives)
            f = this%drives(i)%factor%value(t)
            v = v + f * this%drives(i)%velocity
            omega = omega + f * this%drives(i)%angular_velocity
        end do
    end subroutine drive_twist

    ! ---- The step: one linear system ----------------------------------------------------------

    !> F(Y) = A Y - b with the cached system of this step.
    subroutine strand_step_residual(this, t_n, h, x_n, y, f, status)
        class(se3_strand_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: f(:)
        integer, intent(out) :: status
        integer :: b
        call this%ensure_assembled(t_n, h, x_n, status)
        if (status /= state_valid) return
        do b = 0, this%n_blocks - 1
            call strand_row_residual(this%blocks(:, :, :, b), this%row_blocks(:, b), &
                this%rhs(:, b), y, f(6 * b + 1:6 * b + 6))
        end do
        if (any(f /= f)) status = state_invalid
    end subroutine strand_step_residual

    subroutine strand_step_jacobian(this, t_n, h, x_n, y, values, status)
        class(se3_strand_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: values(:)
        integer, intent(out) :: status
        call this%ensure_assembled(t_n, h, x_n, status)
        if (status /= state_valid) return
        call blocks_to_csr(this, this%blocks, values)
    end subroutine strand_step_jacobian

    !> The blocks (6, 6, 3, 0:n_blocks-1) of a matrix on the step's pattern as its CSR values.
    subroutine blocks_to_csr(this, blocks, values)
        type(se3_strand_t), intent(in) :: this
        real(rk), intent(in) :: blocks(:, :, :, 0:)
        real(rk), intent(out) :: values(:)
        integer :: b, c, i, j, at
        if (this%csr_in_block_order) then
            at = 0
            do b = 0, this%n_blocks - 1
                call strand_row_to_csr(blocks(:, :, :, b), this%n_row_blocks(b), &
                    values(at + 1:at + 36 * this%n_row_blocks(b)))
                at = at + 36 * this%n_row_blocks(b)
            end do
            return
        end if
        do b = 0, this%n_blocks - 1
            do c = 1, 3
                if (this%row_blocks(c, b) < 0) cycle
                do j = 1, 6
                    do i = 1, 6
                        values(this%block_map(i, j, c, b)) = blocks(i, j, c, b)
                    end do
                end do
            end do
        end do
    end subroutine blocks_to_csr

    !> dF/dX_n of the step (rod_formulation_t%state_jacobian, modal_one_step): the frozen
    !> coefficients' dependence on P_n and Sigma_n (ad_{V_n}, ad_{U_n}, U_n = A^-1 Sigma_n +
    !> U_bar, in the node and segment rows of methods/se3_strands.md §3.5), the right-hand
    !> side's P_n / h and Sigma_n / h, the Kelvin-Voigt and internal laws' Sigma_n
    !> (docs/theory/modes.md, "se3_strand"). F is at most quadratic in X_n (the
    !> Kelvin-Voigt right-hand side c(Sigma_n) theta Sigma_n; the rest is affine), so central
    !> differences are exact up to round-off for any step; row b reads X_n's blocks b - 1 .. b +
    !> 1 only, so the columns of blocks three apart are differenced together (18 pairs of
    !> residuals). Not available with dead loads: their directions at t_n come from the
    !> placement marched from s = 0, which couples a node to every segment before it, outside
    !> the pattern.
    subroutine strand_state_jacobian(this, t_n, h, x_n, y, values, status)
        class(se3_strand_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), y(:)
        real(rk), intent(out) :: values(:)
        integer, intent(out) :: status
        real(rk), allocatable :: x_plus(:), x_minus(:), f_plus(:), f_minus(:), steps(:)
        real(rk), allocatable :: derivative(:, :, :, :)
        integer :: first, i, c, b, slot, k, j, n
        values = 0.0_rk
        status = state_invalid
        if (this%needs_pose) return
        n = this%n_unknown()
        allocate(f_plus(n), f_minus(n), steps(0:this%n_blocks - 1))
        allocate(derivative(6, 6, 3, 0:this%n_blocks - 1), source=0.0_rk)
        do first = 0, 2
            do i = 1, 6
                x_plus = x_n
                x_minus = x_n
                do c = first, this%n_blocks - 1, 3
                    j = 6 * c + i
                    if (mod(c, 2) == 1) then
                        ! P_k: a velocity of 1 (m/s or rad/s).
                        k = (c - 1) / 2
                        steps(c) = max(this%mass(i, k), 1.0e-3_rk * abs(x_n(j)))
                    else
                        ! Sigma_k (k = -1 the ghost): a strain of 1e-3.
                        k = c / 2 - 1
                        steps(c) = max(1.0e-3_rk * this%stiff(i, k), 1.0e-3_rk * abs(x_n(j)))
                    end if
                    x_plus(j) = x_n(j) + steps(c)
                    x_minus(j) = x_n(j) - steps(c)
                end do
                call this%step_residual(t_n, h, x_plus, y, f_plus, status)
                if (status == state_valid) &
                    call this%step_residual(t_n, h, x_minus, y, f_minus, status)
                if (status /= state_valid) exit
                do b = 0, this%n_blocks - 1
                    do slot = 1, 3
                        c = this%row_blocks(slot, b)
                        if (c < 0) cycle
                        if (mod(c, 3) /= first) cycle
                        derivative(:, i, slot, b) = (f_plus(6 * b + 1:6 * b + 6) - &
                            f_minus(6 * b + 1:6 * b + 6)) / (2.0_rk * steps(c))
                    end do
                end do
            end do
            if (status /= state_valid) exit
        end do
        ! The cache holds a perturbed step now.
        this%cached = .false.
        if (status /= state_valid) return
        call blocks_to_csr(this, derivative, values)
    end subroutine strand_state_jacobian

    !> Assemble the system of the step (t_n, h, x_n) unless it is the cached one.
    subroutine ensure_assembled(this, t_n, h, x_n, status)
        class(se3_strand_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:)
        integer, intent(out) :: status
        status = state_valid
        if (this%cached .and. t_n == this%key_t .and. h == this%key_h) then
            if (all(x_n == this%key_x)) return
        end if
        call this%assemble(t_n, h, x_n, status)
        this%cached = status == state_valid
        this%key_t = t_n
        this%key_h = h
        this%key_x = x_n
    end subroutine ensure_assembled

    !> The blocks and right-hand side of eqs. (11)-(15) (methods §3.5) with the additions in the
    !> module header. Rows are scaled by 1 (node and segment rows, as written) and 1/h (the
    !> boundary rows), so every diagonal block starts from I/h.
    subroutine assemble(this, t_n, h, x_n, status)
        class(se3_strand_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:)
        integer, intent(out) :: status
        real(rk) :: eye_h(6, 6), p(6), v(6), v_next(6), s_prev(6), s_here(6), u_prev(6)
        real(rk) :: u_here(6), c_prev(6, 6), c_here(6, 6), theta(6), p0(6), diag_p(6), diag_s(6)
        real(rk) :: theta_cols(6, 6), total_cols(6, 6)
        real(rk) :: diag_c(6), quarter_stiff(6), vel(3), omega(3), a0(3, 3), g(3, 3)
        integer :: k, n, b, i
        status = state_valid
        n = this%n_seg
        theta = this%tau_kv / h
        ! theta is diagonal (one time per component): it scales the blocks' columns, by theta
        ! (the viscous part) or 1 + theta (the total stress).
        theta_cols = spread(theta, 1, 6)
        total_cols = 1.0_rk + theta_cols
        ! Every entry of every block in the pattern is written below: no zero fill.
        eye_h = 0.0_rk
        do i = 1, 6
            eye_h(i, i) = 1.0_rk / h
        end do
        diag_s = 1.0_rk / h
        ! The placement at t_n only if a dead load needs its directors.
        if (this%needs_pose) call this%march_poses(x_n)
        call this%distributed_loads(t_n + h)
        call this%end_loads(t_n + h)

        ! Eq. (14): the ghost Sigma_{-1,0} copies Sigma_{0,1}; at a free start it mirrors it,
        ! Sigma_{-1} + Sigma_0 = 0 (eq. 15 with no load, docs/theory/se3_strand.md).
        this%blocks(:, :, 1, 0) = eye_h
        this%blocks(:, :, 2, 0) = -eye_h
        if (this%free_start) this%blocks(:, :, 2, 0) = eye_h
        this%rhs(:, 0) = 0.0_rk
        if (.not. this%free_start) then
            ! Eq. (13): P_0 = M V_0(t_{n+1}), V_0 the prescribed twist in the body frame at
            ! t_{n+1}.
            call this%drive_twist(t_n + h, vel, omega)
            a0 = reshape(x_n(pose_index(this) + 4:pose_index(this) + 12), [3, 3])
            a0 = matmul(exp_so3(h * omega), a0)
            p0(1:3) = -matmul(transpose(a0), omega)
            p0(4:6) = matmul(transpose(a0), vel)
            this%blocks(:, :, 1, 1) = eye_h
            this%rhs(:, 1) = this%mass(:, 0) * p0 / h
        end if

        ! Eq. (11) at the nodes k = 1..N (§3.5), and k = 0 at a free start: blocks
        ! (Sigma_{k-1}, P_k, Sigma_k).
        do k = merge(0, 1, this%free_start), n
            b = 2 * k + 1
            p = p_at(x_n, k)
            v = this%mass_inv(:, k) * p
            diag_p = 1.0_rk / h + this%eta_external * this%mass_inv(:, k)
            s_prev = s_at(x_n, k - 1)
            s_here = s_at(x_n, k)
            u_prev = this%stiff_inv(:, k - 1) * s_prev + this%u_bar(:, k - 1)
            u_here = this%stiff_inv(:, k) * s_here + this%u_bar(:, k)
            diag_c = 1.0_rk / this%dual(k)
            if (k == 0) then
                ! The free start's half cell [0, h/2] takes the ad^T term of its one physical
                ! segment in full, as the balanced free end does (below), so the start adds no
                ! power.
                call strand_ad_transpose_block(u_prev, 0.0_rk, diag_c, c_prev)
                call strand_ad_transpose_block(u_here, 1.0_rk, -diag_c, c_here)
            else if (k < n .or. this%paper_free_end) then
                call strand_ad_transpose_block(u_prev, 0.5_rk, diag_c, c_prev)
                call strand_ad_transpose_block(u_here, 0.5_rk, -diag_c, c_here)
            else
                ! The free end's half cell [s_N - h/2, s_N] (eq. 15 in eq. 11, methods §3.4)
                ! takes the ad^T term of its one physical segment in full: paired with
                ! V_N, it is what segment N-1's compatibility row returns, so the end adds no
                ! power but V_N . Sigma_e. The paper's average with the ghost segment instead
                ! adds (1/2) ad^T_{U_bar} (2 Sigma_e - 2 Sigma_{N-1}): an end moment of about
                ! h |f| / 2 (sigma_bar x f) that no row balances; it created energy and blew up
                ! a 1 m rod under 1e6 N (issue 21 item 12, docs/theory/se3_strand.md); it is
                ! kept as &rod free_end = 'paper' for the paper's h^2 tip table.
                call strand_ad_transpose_block(u_prev, 1.0_rk, diag_c, c_prev)
                call strand_ad_transpose_block(u_here, 0.0_rk, -diag_c, c_here)
            end if
            ! P_k: dP/dt - ad_V^T P + D_ex M^-1 P.
            call strand_ad_transpose_block(v, -1.0_rk, diag_p, this%blocks(:, :, 2, b))
            this%rhs(:, b) = p / h
            ! Stresses, with the Kelvin-Voigt viscous part theta (Sigma - Sigma_n); at k = N the
            ! ghost's viscous stress mirrors Sigma_{N-1}'s, so the end's total stress is the
            ! prescribed one, and at a free start (k = 0) the ghost's mirrors Sigma_0's.
            if (k == 0) then
                this%blocks(:, :, 1, b) = c_prev
                this%blocks(:, :, 3, b) = c_here * total_cols - c_prev * theta_cols
                if (any(theta /= 0.0_rk)) this%rhs(:, b) = this%rhs(:, b) + &
                    matmul(c_here, theta * s_here) - matmul(c_prev, theta * s_here)
            else if (k < n) then
                this%blocks(:, :, 1, b) = c_prev * total_cols
                this%blocks(:, :, 3, b) = c_here * total_cols
                if (any(theta /= 0.0_rk)) this%rhs(:, b) = this%rhs(:, b) + &
                    matmul(c_prev, theta * s_prev) + matmul(c_here, theta * s_here)
            else
                this%blocks(:, :, 1, b) = c_prev * total_cols - c_here * theta_cols
                this%blocks(:, :, 3, b) = c_here
                if (any(theta /= 0.0_rk)) this%rhs(:, b) = this%rhs(:, b) + &
                    matmul(c_prev, theta * s_prev) - matmul(c_here, theta * s_prev)
            end if
            ! The paper's internal law: + D_in A^-1 (Sigma_k - Sigma_k^n) / dt (right segment).
            do i = 1, 6
                this%blocks(i, i, 3, b) = this%blocks(i, i, 3, b) + this%eta_internal * &
                    this%stiff_inv(i, k) / h
            end do
            this%rhs(:, b) = this%rhs(:, b) + this%eta_internal * this%stiff_inv(:, k) * s_here / h
            ! External loads -F_k: paper sign (-torque, force); dead ones turn with the
            ! section, linearized implicitly: f_{n+1} = f - h [f]x w_{n+1}.
            this%rhs(1:3, b) = this%rhs(1:3, b) - this%load_m(:, k) - this%load_m_follower(:, k)
            this%rhs(4:6, b) = this%rhs(4:6, b) + this%load_f(:, k) + this%load_f_follower(:, k)
            if (this%needs_pose) then
                call dead_turn_block(this, k, h, g)
                this%blocks(4:6, 1:3, 2, b) = this%blocks(4:6, 1:3, 2, b) + g
                call dead_moment_turn_block(this, k, h, g)
                this%blocks(1:3, 1:3, 2, b) = this%blocks(1:3, 1:3, 2, b) + g
            end if
        end do

        ! Eq. (12) on the segments k = 0..N-1 (§3.5): blocks (P_k, Sigma_k, P_{k+1}), with the
        ! segment's A and each node's own M (&segment: they differ at a jump).
        do k = 0, n - 1
            b = 2 * k + 2
            v = this%mass_inv(:, k) * p_at(x_n, k)
            v_next = this%mass_inv(:, k + 1) * p_at(x_n, k + 1)
            s_here = s_at(x_n, k)
            u_here = this%stiff_inv(:, k) * s_here + this%u_bar(:, k)
            quarter_stiff = 0.25_rk * this%stiff(:, k)
            ! Sigma_k: I/dt + A ad_{V_k + V_{k+1}} A^-1 / 4.
            call strand_ad_block(v + v_next, quarter_stiff, this%stiff_inv(:, k), diag_s, &
                this%blocks(:, :, 2, b))
            ! P_k and P_{k+1}: +-A M_k^-1 / h_k - A ad_U M_k^-1 / 4 (M_{k+1} for P_{k+1}).
            diag_c = this%stiff(:, k) * this%mass_inv(:, k) / this%seg_h(k)
            call strand_ad_block(u_here, -quarter_stiff, this%mass_inv(:, k), diag_c, &
                this%blocks(:, :, 1, b))
            diag_c = -this%stiff(:, k) * this%mass_inv(:, k + 1) / this%seg_h(k)
            call strand_ad_block(u_here, -quarter_stiff, this%mass_inv(:, k + 1), diag_c, &
                this%blocks(:, :, 3, b))
            this%rhs(:, b) = s_here / h - quarter_stiff * strand_ad_times(v + v_next, &
                this%u_bar(:, k))
        end do

        ! Eq. (15): Sigma_{N-1} + Sigma_N = 2 Sigma_e(t_{n+1}), Sigma_e = (-m, f) in K components.
        b = 2 * n + 2
        this%blocks(:, :, 1, b) = eye_h
        this%blocks(:, :, 2, b) = 0.0_rk
        this%blocks(:, :, 3, b) = eye_h
        this%rhs(1:3, b) = -2.0_rk * (this%end_m + this%end_m_follower) / h
        this%rhs(4:6, b) = 2.0_rk * (this%end_f + this%end_f_follower) / h
        if (this%needs_pose) then
            ! d Sigma_e / d w = (h [m]x ; -h [f]x), w = M^-1 P_N (angular part).
            c_here(1:3, 1:3) = cross_matrix(this%end_m)
            c_here(4:6, 1:3) = cross_matrix(this%end_f)
            do i = 1, 3
                this%blocks(1:3, i, 2, b) = -2.0_rk * c_here(1:3, i) * this%mass_inv(i, n)
                this%blocks(4:6, i, 2, b) = 2.0_rk * c_here(4:6, i) * this%mass_inv(i, n)
            end do
        end if
        if (any(this%rhs /= this%rhs)) status = state_invalid
        do b = 0, this%n_blocks - 1
            if (strand_row_has_nan(this%blocks(:, :, :, b))) status = state_invalid
        end do
    end subroutine assemble

    !> d(-F_lin)/dP_ang of a node's dead force density f (K components at t_n):
    !> f_{n+1} = f - h [f]x w gives h [f]x M_ang^-1.
    subroutine dead_turn_block(this, k, h, g)
        type(se3_strand_t), intent(in) :: this
        integer, intent(in) :: k
        real(rk), intent(in) :: h
        real(rk), intent(out) :: g(3, 3)
        integer :: j
        g = h * cross_matrix(this%load_f(:, k))
        do j = 1, 3
            g(:, j) = g(:, j) * this%mass_inv(j, k)
        end do
    end subroutine dead_turn_block

    !> The same for a dead torque density t: F_ang = -(t - h [t]x w), so d(-F_ang)/dP_ang =
    !> -h [t]x M_ang^-1.
    subroutine dead_moment_turn_block(this, k, h, g)
        type(se3_strand_t), intent(in) :: this
        integer, intent(in) :: k
        real(rk), intent(in) :: h
        real(rk), intent(out) :: g(3, 3)
        integer :: j
        g = -h * cross_matrix(this%load_m(:, k))
        do j = 1, 3
            g(:, j) = g(:, j) * this%mass_inv(j, k)
        end do
    end subroutine dead_moment_turn_block

    !> The placement at the nodes from the pose at s = 0 and the segment strains of x
    !> (Appendix A: marched with the closed-form exponential).
    subroutine march_poses(this, x)
        class(se3_strand_t), intent(inout) :: this
        real(rk), intent(in) :: x(:)
        real(rk) :: u(6)
        integer :: k
        this%pose_x(:, 0) = x(pose_index(this) + 1:pose_index(this) + 3)
        this%pose_a(:, :, 0) = reshape(x(pose_index(this) + 4:pose_index(this) + 12), [3, 3])
        do k = 0, this%n_seg - 1
            u = this%stiff_inv(:, k) * s_at(x, k) + this%u_bar(:, k)
            call strand_march(this%pose_a(:, :, k), this%pose_x(:, k), u, this%seg_h(k), &
                this%pose_a(:, :, k + 1), this%pose_x(:, k + 1))
        end do
    end subroutine march_poses

    !> Distributed force and torque densities at the nodes at time t in K components: dead ones
    !> with the directors of pose_a (load_f, load_m), follower ones as given (load_f_follower,
    !> load_m_follower), apart since only the dead ones turn with the section. Node 0 is held,
    !> but filled alike.
    subroutine distributed_loads(this, t)
        class(se3_strand_t), intent(inout) :: this
        real(rk), intent(in) :: t
        real(rk) :: f
        integer :: i, k
        this%load_f = 0.0_rk
        this%load_m = 0.0_rk
        this%load_f_follower = 0.0_rk
        this%load_m_follower = 0.0_rk
        do i = 1, size(this%loads)
            associate (load => this%loads(i))
                if (load%at_end) cycle
                f = load%factor%value(t)
                if (f == 0.0_rk) cycle
                do k = 0, this%n_seg
                    if (load%per_mass) then
                        this%load_f(:, k) = this%load_f(:, k) + f * this%mass(4, k) * &
                            matmul(load%force, this%pose_a(:, :, k))
                    else if (load%follower) then
                        this%load_f_follower(:, k) = this%load_f_follower(:, k) + f * load%force
                        this%load_m_follower(:, k) = this%load_m_follower(:, k) + f * load%moment
                    else
                        this%load_f(:, k) = this%load_f(:, k) + f * matmul(load%force, this%pose_a(:, :, k))
                        this%load_m(:, k) = this%load_m(:, k) + f * matmul(load%moment, this%pose_a(:, :, k))
                    end if
                end do
            end associate
        end do
    end subroutine distributed_loads

    !> End force and moment at s = L at time t in K components: dead ones (turned with the
    !> tip, end_f, end_m) and follower ones apart, since only the dead ones are linearized.
    subroutine end_loads(this, t)
        class(se3_strand_t), intent(inout) :: this
        real(rk), intent(in) :: t
        real(rk) :: f
        integer :: i, n
        n = this%n_seg
        this%end_f = 0.0_rk
        this%end_m = 0.0_rk
        this%end_f_follower = 0.0_rk
        this%end_m_follower = 0.0_rk
        do i = 1, size(this%loads)
            associate (load => this%loads(i))
                if (.not. load%at_end) cycle
                f = load%factor%value(t)
                if (load%follower) then
                    this%end_f_follower = this%end_f_follower + f * load%force
                    this%end_m_follower = this%end_m_follower + f * load%moment
                else
                    this%end_f = this%end_f + f * matmul(load%force, this%pose_a(:, :, n))
                    this%end_m = this%end_m + f * matmul(load%moment, this%pose_a(:, :, n))
                end if
            end associate
        end do
    end subroutine end_loads

    ! ---- After a step -------------------------------------------------------------------------

    !> The energy terms of the step (terms(1), docs/theory/se3_strand.md): the work of the loads
    !> with the velocities at t_{n+1} (the scheme's implicit level) and the loads as the step
    !> applied them, the energy dissipated by the external drag, the paper's internal law (which
    !> may be negative) and the Kelvin-Voigt stress, and H_n, H_{n+1}, whose balance
    !> H_{n+1} - H_n - W + D (the scheme's own energy error: backward-Euler dissipation and the
    !> O(dt) exchange of the frozen coefficients, either sign; not round-off) the record ledger
    !> sums and the energy sentinel checks; and the achieved residual of the linear solve.
    subroutine strand_accept_step(this, t_n, h, x_n, x_1, terms)
        class(se3_strand_t), intent(inout) :: this
        real(rk), intent(in) :: t_n, h, x_n(:), x_1(:)
        type(step_energy_t), intent(out) :: terms(:)
        real(rk) :: work, dissipated, kin_n, str_n, kin_1, str_1, v(6), rate(6), f(6), r(6)
        real(rk) :: w(3), se(6), res
        integer :: k, n, b, status
        n = this%n_seg
        call this%ensure_assembled(t_n, h, x_n, status)
        ! The achieved residual of the linear solve, max-norm.
        res = 0.0_rk
        do b = 0, this%n_blocks - 1
            call strand_row_residual(this%blocks(:, :, :, b), this%row_blocks(:, b), &
                this%rhs(:, b), x_1, r)
            res = max(res, maxval(abs(r)))
        end do
        work = 0.0_rk
        dissipated = 0.0_rk
        do k = merge(0, 1, this%free_start), n
            v = this%mass_inv(:, k) * p_at(x_1, k)
            w = v(1:3)
            ! F_k as the step applied it (dead loads turned by h w x f, follower ones as given).
            f(1:3) = -(this%load_m(:, k) + h * strand_cross(w, this%load_m(:, k)) + &
                this%load_m_follower(:, k))
            f(4:6) = this%load_f(:, k) + h * strand_cross(w, this%load_f(:, k)) + &
                this%load_f_follower(:, k)
            work = work + h * this%weight(k) * dot_product(v, f)
            dissipated = dissipated + h * this%weight(k) * dot_product(v, this%eta_external * v)
            rate = this%stiff_inv(:, k) * (s_at(x_1, k) - s_at(x_n, k)) / h
            dissipated = dissipated + h * this%weight(k) * this%eta_internal * dot_product(v, rate)
        end do
        ! The end load's power V_N . Sigma_e.
        v = this%mass_inv(:, n) * p_at(x_1, n)
        w = v(1:3)
        se(1:3) = -(this%end_m + h * strand_cross(w, this%end_m) + this%end_m_follower)
        se(4:6) = this%end_f + h * strand_cross(w, this%end_f) + this%end_f_follower
        work = work + h * dot_product(v, se)
        ! The driven start's power: V_0 against the total stress the rod takes there (elastic
        ! and Kelvin-Voigt, as node 1's row uses it), and the kinetic energy of the half cell at
        ! s = 0, whose momentum P_0 = M V_0 the drive prescribes (eq. 13: no balance row moves
        ! it, so the drive supplies its change).
        if (.not. this%free_start) then
            v = this%mass_inv(:, 0) * p_at(x_1, 0)
            work = work - h * dot_product(v, s_at(x_1, 0) + this%tau_kv * (s_at(x_1, 0) - &
                s_at(x_n, 0)) / h)
            work = work + 0.5_rk * this%weight(0) * (dot_product(p_at(x_1, 0), v) - &
                dot_product(p_at(x_n, 0), this%mass_inv(:, 0) * p_at(x_n, 0)))
        end if
        do k = 0, n - 1
            rate = (s_at(x_1, k) - s_at(x_n, k)) / h
            dissipated = dissipated + h * this%seg_h(k) * dot_product(this%tau_kv * rate, &
                this%stiff_inv(:, k) * rate)
        end do
        call this%energies(x_n, kin_n, str_n)
        call this%energies(x_1, kin_1, str_1)
        ! SNES ksponly computes no norm (the solver reports 0): the achieved residual is res.
        terms(1) = step_energy_t(reported=.true., before=kin_n + str_n, after=kin_1 + str_1, &
            work=work, dissipated=dissipated, residual=res)
    end subroutine strand_accept_step

    !> Kinetic energy sum_k w_k P.M^-1 P / 2 (trapezoidal nodal weights) and strain energy
    !> sum_k h_k Sigma.A^-1 Sigma / 2 over the physical segments.
    subroutine energies(this, x, kinetic, strain)
        class(se3_strand_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        real(rk), intent(out) :: kinetic, strain
        real(rk) :: p(6), s(6)
        integer :: k
        kinetic = 0.0_rk
        strain = 0.0_rk
        do k = 0, this%n_seg
            p = p_at(x, k)
            kinetic = kinetic + 0.5_rk * this%weight(k) * dot_product(p, this%mass_inv(:, k) * p)
        end do
        do k = 0, this%n_seg - 1
            s = s_at(x, k)
            strain = strain + 0.5_rk * this%seg_h(k) * dot_product(s, this%stiff_inv(:, k) * s)
        end do
    end subroutine energies

    !> The kinetic energy of x (energies); no rotation measure (no continuation).
    function strand_state_measures(this, x, from) result(measures)
        class(se3_strand_t), intent(in) :: this
        real(rk), intent(in) :: x(:)
        real(rk), intent(in), optional :: from(:)
        type(state_measures_t) :: measures
        real(rk) :: strain
        call this%energies(x, measures%kinetic_energy, strain)
    end function strand_state_measures

    ! ---- Output (DESIGN.md §7) ---------------------------------------------------------------

    subroutine strand_init_history(this, histories, capacity)
        class(se3_strand_t), intent(in) :: this
        type(rod_history_t), intent(inout), target :: histories(:)
        integer, intent(in) :: capacity
        integer :: k
        call histories(1)%init(this%name, 'se3_strand', this%n_seg + 1, this%n_seg, capacity)
        histories(1)%mesh = [(this%length * real(k, rk) / real(this%n_seg, rk), k = 0, this%n_seg)]
        histories(1)%stress_mesh = [(this%length * (real(k, rk) + 0.5_rk) / real(this%n_seg, rk), &
            k = 0, this%n_seg - 1)]
        deallocate(histories(1)%constraint_residual)
    end subroutine strand_init_history

    !> The placement rebuilt from the strains; velocities and director rates from V at the nodes
    !> (standard signs: omega = -A w); stresses and strains at the segment midpoints in director
    !> components with the standard signs (N1, N2, N3, M1, M2, M3) = (S5, S6, S4, -S2, -S3, -S1),
    !> strains (Gamma1, Gamma2, Gamma3, K1, K2, K3) = (U5, U6, U4, -U2, -U3, -U1) (Gamma3 = 1
    !> unstretched); energies; momenta. The sums since the last record are the ledger's.
    subroutine strand_record(this, histories, t, x)
        class(se3_strand_t), intent(inout) :: this
        type(rod_history_t), intent(inout), target :: histories(:)
        real(rk), intent(in) :: t, x(:)
        real(rk) :: a(3, 3), v(6), u(6), s(6), omega(3), vel(3), kinetic, strain, p(6)
        real(rk) :: linear(3), angular(3), centre(3)
        integer :: rec, k
        integer, parameter :: director_column(3) = [2, 3, 1]
        rec = histories(1)%next_record()
        if (rec == 0) return
        call this%march_poses(x)
        associate (hs => histories(1))
            hs%time(rec) = t
            linear = 0.0_rk
            angular = 0.0_rk
            centre = 0.0_rk
            do k = 0, this%n_seg
                a = this%pose_a(:, :, k)
                p = p_at(x, k)
                v = this%mass_inv(:, k) * p
                omega = -matmul(a, v(1:3))
                vel = matmul(a, v(4:6))
                hs%position(:, k + 1, rec) = this%pose_x(:, k)
                hs%velocity(:, k + 1, rec) = vel
                hs%directors(:, :, k + 1, rec) = a(:, director_column)
                hs%director_velocity(:, 1, k + 1, rec) = matmul(hat(omega), a(:, 2))
                hs%director_velocity(:, 2, k + 1, rec) = matmul(hat(omega), a(:, 3))
                hs%director_velocity(:, 3, k + 1, rec) = matmul(hat(omega), a(:, 1))
                linear = linear + this%weight(k) * matmul(a, p(4:6))
                angular = angular + this%weight(k) * (matmul(hat(this%pose_x(:, k)), matmul(a, p(4:6))) - &
                    matmul(a, p(1:3)))
                centre = centre + this%weight(k) * this%mass(4, k) * this%pose_x(:, k)
            end do
            do k = 0, this%n_seg - 1
                s = s_at(x, k)
                u = this%stiff_inv(:, k) * s + this%u_bar(:, k)
                hs%stress(:, k + 1, rec) = [s(5), s(6), s(4), -s(2), -s(3), -s(1)]
                hs%strains(:, k + 1, rec) = [u(5), u(6), u(4), -u(2), -u(3), -u(1)]
            end do
            call this%energies(x, kinetic, strain)
            hs%kinetic(rec) = kinetic
            hs%strain(rec) = strain
            hs%total(rec) = kinetic + strain
            hs%linear_momentum(:, rec) = linear
            hs%angular_momentum(:, rec) = angular
            hs%center_of_mass(:, rec) = centre / sum(this%weight * this%mass(4, :))
        end associate
    end subroutine strand_record

    function strand_describe(this) result(text)
        class(se3_strand_t), intent(in) :: this
        character(len=:), allocatable :: text
        text = 'rod ''' // this%name // ''': se3_strand, ' // str(this%n_seg) // &
            ' segments on a staggered grid, ' // str(this%n_unknown()) // ' unknowns, ' // &
            str(this%pattern%nnz()) // ' matrix non-zeros, one linear solve per step'
    end function strand_describe

    !> The traits of the SE(3) strand:
    !> - native LU: every diagonal block starts from I/dt and the LU needs no pivoting on every
    !>   benchmark (5 times faster than MUMPS at N = 80, docs/performance.md); MUMPS through
    !>   -pc_factor_mat_solver_type mumps where it would;
    !> - banded: the interleaved unknowns are block tridiagonal, the LU keeps their order;
    !> - linear step: the step problem is linear in Y (coefficients frozen at t_n), one solve,
    !>   no Newton loop;
    !> - energy: the semi-implicit scheme has backward-Euler dissipation and a first-order
    !>   energy exchange of the frozen coefficients (docs/theory/se3_strand.md, "Energy
    !>   book-keeping").
    pure function strand_traits(this) result(traits)
        class(se3_strand_t), intent(in) :: this
        type(formulation_traits_t) :: traits
        traits%native_lu = .true.
        traits%banded_unknowns = .true.
        traits%linear_step = .true.
        traits%energy_scheme = energy_dissipative
        traits%modal_form = modal_one_step
    end function strand_traits

end module rs_se3_strand
