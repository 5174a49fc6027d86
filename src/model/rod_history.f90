!> What a run keeps of one rod for the output file (DESIGN.md §7): the stored steps of its
!> nodal fields and its per-step series, as plain data. The formulation fills it; src/io writes
!> it. Arrays are in Fortran order, the step index last, so a record is contiguous; the HDF5
!> datasets show them reversed ([steps x nodes x 3]).
module rs_model_rod_history
    use rs_core_kinds, only: rk
    implicit none
    private

    !> Stored steps and series of one rod. `init` fixes the most records it may hold
    !> (`capacity`, the flush window) but allocates room for a few only: the arrays double when
    !> full, up to the capacity, so memory grows with what is stored, not with `flush_every`
    !> (issue 21 item 17: flush_every = 1000000 preallocated gigabytes for a 5-step run).
    !> `n_stored` counts the records written so far.
    type, public :: rod_history_t
        character(len=:), allocatable :: name
        character(len=:), allocatable :: formulation
        integer :: n_nodes = 0
        !> Stress points: element stress coefficients in element order (n_elements x degree).
        integer :: n_stress_points = 0
        !> Generalized-Maxwell branches (methods/ph_director_3d.md §3.1); 0 for an elastic rod.
        integer :: n_branches = 0
        integer :: n_stored = 0
        !> The most records the history may hold (the `capacity` of `init`).
        integer :: capacity = 0
        !> Reference arc length of the nodes and of the stress points.
        real(rk), allocatable :: mesh(:)
        real(rk), allocatable :: stress_mesh(:)
        real(rk), allocatable :: time(:)
        !> position(:, node, step): centreline.
        real(rk), allocatable :: position(:, :, :)
        !> directors(:, i, node, step) = d_i.
        real(rk), allocatable :: directors(:, :, :, :)
        !> velocity(:, node, step): centreline velocity.
        real(rk), allocatable :: velocity(:, :, :)
        !> director_velocity(:, i, node, step) = time derivative of d_i.
        real(rk), allocatable :: director_velocity(:, :, :, :)
        !> stress(:, point, step) = (N1, N2, N3, M1, M2, M3), material components: the total
        !> stress, elastic branch plus all Maxwell branches.
        real(rk), allocatable :: stress(:, :, :)
        !> strains(:, point, step) = (Gamma1, Gamma2, Gamma3, K1, K2, K3), material components,
        !> computed from the displacements.
        real(rk), allocatable :: strains(:, :, :)
        !> branch_stress(:, point, branch, step): stress of each Maxwell branch, components as
        !> `stress`; allocated only when n_branches > 0.
        real(rk), allocatable :: branch_stress(:, :, :, :)
        !> Energies at the stored steps: kinetic, strain (complementary), total H.
        real(rk), allocatable :: kinetic(:), strain(:), total(:)
        !> Work W_ext of the external loads and energy-balance error
        !> H_{n+1} - H_n - W_ext - W_act + D, summed over the steps since the previous stored step
        !> (methods/ph_director_3d.md §5.3, §3.1; §9 item 7 for the sign of D).
        real(rk), allocatable :: external_work(:), balance_error(:)
        !> Energy D dissipated by the Maxwell branches and work W_act of the actuators, summed
        !> over the steps since the previous stored step (zeros for a rod without them).
        real(rk), allocatable :: dissipated(:), actuator_work(:)
        !> Total linear and angular momentum about the origin, (3, step).
        real(rk), allocatable :: linear_momentum(:, :), angular_momentum(:, :)
        !> Centre of mass (1/L) int phi ds, (3, step).
        real(rk), allocatable :: center_of_mass(:, :)
        !> Largest nodal orthonormality residual max_k |g(d_k)|.
        real(rk), allocatable :: constraint_residual(:)
        !> Newton iterations and final residual norm of the step that ended at this record.
        integer, allocatable :: newton_iterations(:)
        real(rk), allocatable :: newton_residual(:)
        !> Time step that ended at this record (after any cut-backs, the smallest substep).
        real(rk), allocatable :: dt(:)
        !> Load time of each record of an arc-length continuation (&time continuation), whose
        !> records are the path's steps; allocated only there (init_load_time).
        real(rk), allocatable :: load_time(:)
        !> Rods of a bundle (issue 10; allocated by init_coupling): the rod's share of the
        !> contact energy (half of each of its pairs), the total contact force on it, its
        !> deepest contact penetration r_c - d (0 without contact), and the forces of joints and
        !> plates on its two ends, tie_force(:, end, step) with end 1 = start, 2 = end, and
        !> their moments tie_moment (spatial components, about the end's node); the friction of
        !> the step that ended at the record: the friction force on the rod and the largest slip
        !> speed of its contact points.
        real(rk), allocatable :: contact_energy(:), penetration(:), slip_speed(:)
        real(rk), allocatable :: contact_force(:, :), tie_force(:, :, :), tie_moment(:, :, :)
        real(rk), allocatable :: friction_force(:, :)
    contains
        !> The bundle series, with room for as many records as the other arrays.
        procedure :: init_coupling => rod_history_init_coupling
        !> The load-time series of a continuation, with room for as many records as the rest.
        procedure :: init_load_time => rod_history_init_load_time
        procedure :: init => rod_history_init
        procedure :: free => rod_history_free
        procedure :: next_record => rod_history_next_record
        !> Forget the stored records (after they went to the file); the capacity stays.
        procedure :: clear => rod_history_clear
        procedure, private :: grow => rod_history_grow
    end type rod_history_t

    !> Records allocated by `init` (fewer when the capacity is smaller).
    integer, parameter :: initial_records = 8

contains

    !> A history of at most `capacity` records of a rod with `n_nodes` nodes, `n_stress_points`
    !> stress points and `n_branches` (>= 0; default 0) Maxwell branches; room for a few
    !> records is allocated now, the rest as records come (`next_record`).
    subroutine rod_history_init(this, name, formulation, n_nodes, n_stress_points, capacity, &
            n_branches)
        class(rod_history_t), intent(inout) :: this
        character(len=*), intent(in) :: name, formulation
        integer, intent(in) :: n_nodes, n_stress_points, capacity
        integer, intent(in), optional :: n_branches
        integer :: room
        call this%free()
        this%capacity = max(capacity, 0)
        room = min(this%capacity, initial_records)
        this%name = name
        this%formulation = formulation
        this%n_nodes = n_nodes
        this%n_stress_points = n_stress_points
        if (present(n_branches)) this%n_branches = n_branches
        allocate(this%mesh(n_nodes), this%stress_mesh(n_stress_points), source=0.0_rk)
        allocate(this%time(room), this%kinetic(room), this%strain(room), &
            this%total(room), this%external_work(room), this%balance_error(room), &
            this%dissipated(room), this%actuator_work(room), &
            this%constraint_residual(room), this%newton_residual(room), &
            this%dt(room), source=0.0_rk)
        allocate(this%newton_iterations(room), source=0)
        allocate(this%position(3, n_nodes, room), this%velocity(3, n_nodes, room), &
            source=0.0_rk)
        allocate(this%directors(3, 3, n_nodes, room), &
            this%director_velocity(3, 3, n_nodes, room), source=0.0_rk)
        allocate(this%stress(6, n_stress_points, room), &
            this%strains(6, n_stress_points, room), source=0.0_rk)
        if (this%n_branches > 0) allocate(this%branch_stress(6, n_stress_points, &
            this%n_branches, room), source=0.0_rk)
        allocate(this%linear_momentum(3, room), this%angular_momentum(3, room), &
            this%center_of_mass(3, room), source=0.0_rk)
    end subroutine rod_history_init

    !> Deallocate everything and reset the counts.
    subroutine rod_history_free(this)
        class(rod_history_t), intent(inout) :: this
        this%n_stored = 0
        this%capacity = 0
        this%n_nodes = 0
        this%n_stress_points = 0
        this%n_branches = 0
        if (allocated(this%name)) deallocate(this%name)
        if (allocated(this%formulation)) deallocate(this%formulation)
        ! One by one: a formulation may drop arrays it has no data for.
        if (allocated(this%mesh)) deallocate(this%mesh)
        if (allocated(this%stress_mesh)) deallocate(this%stress_mesh)
        if (allocated(this%time)) deallocate(this%time)
        if (allocated(this%kinetic)) deallocate(this%kinetic)
        if (allocated(this%strain)) deallocate(this%strain)
        if (allocated(this%total)) deallocate(this%total)
        if (allocated(this%external_work)) deallocate(this%external_work)
        if (allocated(this%balance_error)) deallocate(this%balance_error)
        if (allocated(this%dissipated)) deallocate(this%dissipated)
        if (allocated(this%actuator_work)) deallocate(this%actuator_work)
        if (allocated(this%constraint_residual)) deallocate(this%constraint_residual)
        if (allocated(this%newton_residual)) deallocate(this%newton_residual)
        if (allocated(this%dt)) deallocate(this%dt)
        if (allocated(this%load_time)) deallocate(this%load_time)
        if (allocated(this%newton_iterations)) deallocate(this%newton_iterations)
        if (allocated(this%position)) deallocate(this%position)
        if (allocated(this%velocity)) deallocate(this%velocity)
        if (allocated(this%directors)) deallocate(this%directors)
        if (allocated(this%director_velocity)) deallocate(this%director_velocity)
        if (allocated(this%stress)) deallocate(this%stress)
        if (allocated(this%strains)) deallocate(this%strains)
        if (allocated(this%branch_stress)) deallocate(this%branch_stress)
        if (allocated(this%linear_momentum)) deallocate(this%linear_momentum)
        if (allocated(this%angular_momentum)) deallocate(this%angular_momentum)
        if (allocated(this%center_of_mass)) deallocate(this%center_of_mass)
        if (allocated(this%contact_energy)) deallocate(this%contact_energy)
        if (allocated(this%penetration)) deallocate(this%penetration)
        if (allocated(this%contact_force)) deallocate(this%contact_force)
        if (allocated(this%tie_force)) deallocate(this%tie_force)
        if (allocated(this%tie_moment)) deallocate(this%tie_moment)
        if (allocated(this%friction_force)) deallocate(this%friction_force)
        if (allocated(this%slip_speed)) deallocate(this%slip_speed)
    end subroutine rod_history_free

    !> `capacity` is the history's own (kept as an argument for the formulations' calls).
    subroutine rod_history_init_coupling(this, capacity)
        class(rod_history_t), intent(inout) :: this
        integer, intent(in) :: capacity
        integer :: room
        room = size(this%time)
        if (capacity < room) room = max(capacity, 0)
        allocate(this%contact_energy(room), this%penetration(room), source=0.0_rk)
        allocate(this%contact_force(3, room), this%tie_force(3, 2, room), &
            this%tie_moment(3, 2, room), this%friction_force(3, room), this%slip_speed(room), &
            source=0.0_rk)
    end subroutine rod_history_init_coupling

    subroutine rod_history_init_load_time(this)
        class(rod_history_t), intent(inout) :: this
        allocate(this%load_time(size(this%time)), source=0.0_rk)
    end subroutine rod_history_init_load_time

    !> Index of the next record (the arrays grown if they are full), or 0 when the capacity
    !> is used up.
    function rod_history_next_record(this) result(record)
        class(rod_history_t), intent(inout) :: this
        integer :: record
        if (this%n_stored >= this%capacity) then
            record = 0
            return
        end if
        if (this%n_stored >= size(this%time)) &
            call this%grow(min(this%capacity, max(2 * size(this%time), initial_records)))
        this%n_stored = this%n_stored + 1
        record = this%n_stored
    end function rod_history_next_record

    !> Room for `room` records in every allocated array (the stored records kept); arrays a
    !> formulation dropped stay unallocated.
    subroutine rod_history_grow(this, room)
        class(rod_history_t), intent(inout) :: this
        integer, intent(in) :: room
        call grow_1(this%time)
        call grow_1(this%kinetic)
        call grow_1(this%strain)
        call grow_1(this%total)
        call grow_1(this%external_work)
        call grow_1(this%balance_error)
        call grow_1(this%dissipated)
        call grow_1(this%actuator_work)
        call grow_1(this%constraint_residual)
        call grow_1(this%newton_residual)
        call grow_1(this%dt)
        call grow_1(this%load_time)
        call grow_1(this%contact_energy)
        call grow_1(this%penetration)
        call grow_integer(this%newton_iterations)
        call grow_2(this%linear_momentum)
        call grow_2(this%angular_momentum)
        call grow_2(this%center_of_mass)
        call grow_2(this%contact_force)
        call grow_3(this%position)
        call grow_3(this%velocity)
        call grow_3(this%stress)
        call grow_3(this%strains)
        call grow_3(this%tie_force)
        call grow_3(this%tie_moment)
        call grow_2(this%friction_force)
        call grow_1(this%slip_speed)
        call grow_4(this%directors)
        call grow_4(this%director_velocity)
        call grow_4(this%branch_stress)
    contains
        ! The last dimension counts records; the first n_stored are copied.
        subroutine grow_1(values)
            real(rk), allocatable, intent(inout) :: values(:)
            real(rk), allocatable :: grown(:)
            if (.not. allocated(values)) return
            allocate(grown(room), source=0.0_rk)
            grown(1:this%n_stored) = values(1:this%n_stored)
            call move_alloc(grown, values)
        end subroutine grow_1

        subroutine grow_integer(values)
            integer, allocatable, intent(inout) :: values(:)
            integer, allocatable :: grown(:)
            if (.not. allocated(values)) return
            allocate(grown(room), source=0)
            grown(1:this%n_stored) = values(1:this%n_stored)
            call move_alloc(grown, values)
        end subroutine grow_integer

        subroutine grow_2(values)
            real(rk), allocatable, intent(inout) :: values(:, :)
            real(rk), allocatable :: grown(:, :)
            if (.not. allocated(values)) return
            allocate(grown(size(values, 1), room), source=0.0_rk)
            grown(:, 1:this%n_stored) = values(:, 1:this%n_stored)
            call move_alloc(grown, values)
        end subroutine grow_2

        subroutine grow_3(values)
            real(rk), allocatable, intent(inout) :: values(:, :, :)
            real(rk), allocatable :: grown(:, :, :)
            if (.not. allocated(values)) return
            allocate(grown(size(values, 1), size(values, 2), room), source=0.0_rk)
            grown(:, :, 1:this%n_stored) = values(:, :, 1:this%n_stored)
            call move_alloc(grown, values)
        end subroutine grow_3

        subroutine grow_4(values)
            real(rk), allocatable, intent(inout) :: values(:, :, :, :)
            real(rk), allocatable :: grown(:, :, :, :)
            if (.not. allocated(values)) return
            allocate(grown(size(values, 1), size(values, 2), size(values, 3), room), &
                source=0.0_rk)
            grown(:, :, :, 1:this%n_stored) = values(:, :, :, 1:this%n_stored)
            call move_alloc(grown, values)
        end subroutine grow_4
    end subroutine rod_history_grow

    subroutine rod_history_clear(this)
        class(rod_history_t), intent(inout) :: this
        this%n_stored = 0
    end subroutine rod_history_clear

end module rs_model_rod_history
