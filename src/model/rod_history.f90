!> What a run keeps of one rod for the output file (DESIGN.md §7): the stored steps of its
!> nodal fields and its per-step series, as plain data. The formulation fills it; src/io writes
!> it. Arrays are in Fortran order, the step index last, so a record is contiguous; the HDF5
!> datasets show them reversed ([steps x nodes x 3]).
module rs_model_rod_history
    use rs_core_kinds, only: rk
    implicit none
    private

    !> Stored steps and series of one rod. Capacity is fixed at `init`; `n_stored` counts the
    !> records written so far.
    type, public :: rod_history_t
        character(len=:), allocatable :: name
        character(len=:), allocatable :: formulation
        integer :: n_nodes = 0
        !> Stress points: element stress coefficients in element order (n_elements x degree).
        integer :: n_stress_points = 0
        !> Generalized-Maxwell branches (methods/ph_director_3d.md §3.1); 0 for an elastic rod.
        integer :: n_branches = 0
        integer :: n_stored = 0
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
    contains
        procedure :: init => rod_history_init
        procedure :: free => rod_history_free
        procedure :: next_record => rod_history_next_record
        !> Forget the stored records (after they went to the file); the capacity stays.
        procedure :: clear => rod_history_clear
        procedure :: pack => rod_history_pack
        procedure :: unpack => rod_history_unpack
    end type rod_history_t

contains

    !> Allocate room for `capacity` records of a rod with `n_nodes` nodes, `n_stress_points`
    !> stress points and `n_branches` (>= 0; default 0) Maxwell branches.
    subroutine rod_history_init(this, name, formulation, n_nodes, n_stress_points, capacity, &
            n_branches)
        class(rod_history_t), intent(inout) :: this
        character(len=*), intent(in) :: name, formulation
        integer, intent(in) :: n_nodes, n_stress_points, capacity
        integer, intent(in), optional :: n_branches
        call this%free()
        this%name = name
        this%formulation = formulation
        this%n_nodes = n_nodes
        this%n_stress_points = n_stress_points
        if (present(n_branches)) this%n_branches = n_branches
        allocate(this%mesh(n_nodes), this%stress_mesh(n_stress_points), source=0.0_rk)
        allocate(this%time(capacity), this%kinetic(capacity), this%strain(capacity), &
            this%total(capacity), this%external_work(capacity), this%balance_error(capacity), &
            this%dissipated(capacity), this%actuator_work(capacity), &
            this%constraint_residual(capacity), this%newton_residual(capacity), &
            this%dt(capacity), source=0.0_rk)
        allocate(this%newton_iterations(capacity), source=0)
        allocate(this%position(3, n_nodes, capacity), this%velocity(3, n_nodes, capacity), &
            source=0.0_rk)
        allocate(this%directors(3, 3, n_nodes, capacity), &
            this%director_velocity(3, 3, n_nodes, capacity), source=0.0_rk)
        allocate(this%stress(6, n_stress_points, capacity), &
            this%strains(6, n_stress_points, capacity), source=0.0_rk)
        if (this%n_branches > 0) allocate(this%branch_stress(6, n_stress_points, &
            this%n_branches, capacity), source=0.0_rk)
        allocate(this%linear_momentum(3, capacity), this%angular_momentum(3, capacity), &
            this%center_of_mass(3, capacity), source=0.0_rk)
    end subroutine rod_history_init

    !> Deallocate everything and reset the counts.
    subroutine rod_history_free(this)
        class(rod_history_t), intent(inout) :: this
        this%n_stored = 0
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
    end subroutine rod_history_free

    !> Index of the next record, or 0 when the capacity is used up.
    function rod_history_next_record(this) result(record)
        class(rod_history_t), intent(inout) :: this
        integer :: record
        if (this%n_stored >= size(this%time)) then
            record = 0
        else
            this%n_stored = this%n_stored + 1
            record = this%n_stored
        end if
    end function rod_history_next_record

    subroutine rod_history_clear(this)
        class(rod_history_t), intent(inout) :: this
        this%n_stored = 0
    end subroutine rod_history_clear

    !> The stored records as two flat arrays, for sending to another rank (`unpack` inverts).
    subroutine rod_history_pack(this, header, values)
        class(rod_history_t), intent(in) :: this
        integer, allocatable, intent(out) :: header(:)
        real(rk), allocatable, intent(out) :: values(:)
        real(rk), allocatable :: branches(:)
        integer :: n, i
        n = this%n_stored
        header = [this%n_nodes, this%n_stress_points, n, len(this%name), len(this%formulation), &
            this%n_branches, this%newton_iterations(1:n), &
            (ichar(this%name(i:i)), i = 1, len(this%name)), &
            (ichar(this%formulation(i:i)), i = 1, len(this%formulation))]
        allocate(branches(0))
        if (this%n_branches > 0) branches = reshape(this%branch_stress(:, :, :, 1:n), &
            [6 * this%n_stress_points * this%n_branches * n])
        values = [this%mesh, this%stress_mesh, this%time(1:n), &
            reshape(this%position(:, :, 1:n), [3 * this%n_nodes * n]), &
            reshape(this%directors(:, :, :, 1:n), [9 * this%n_nodes * n]), &
            reshape(this%velocity(:, :, 1:n), [3 * this%n_nodes * n]), &
            reshape(this%director_velocity(:, :, :, 1:n), [9 * this%n_nodes * n]), &
            reshape(this%stress(:, :, 1:n), [6 * this%n_stress_points * n]), &
            reshape(this%strains(:, :, 1:n), [6 * this%n_stress_points * n]), branches, &
            this%kinetic(1:n), this%strain(1:n), this%total(1:n), this%external_work(1:n), &
            this%balance_error(1:n), this%dissipated(1:n), this%actuator_work(1:n), &
            reshape(this%linear_momentum(:, 1:n), [3 * n]), &
            reshape(this%angular_momentum(:, 1:n), [3 * n]), &
            reshape(this%center_of_mass(:, 1:n), [3 * n]), this%constraint_residual(1:n), &
            this%newton_residual(1:n), this%dt(1:n)]
    end subroutine rod_history_pack

    !> Rebuild a history from what `pack` produced.
    subroutine rod_history_unpack(this, header, values)
        class(rod_history_t), intent(inout) :: this
        integer, intent(in) :: header(:)
        real(rk), intent(in) :: values(:)
        integer :: n, nn, ns, nb, at, i
        character(len=:), allocatable :: name, formulation
        nn = header(1)
        ns = header(2)
        n = header(3)
        allocate(character(len=header(4)) :: name)
        allocate(character(len=header(5)) :: formulation)
        nb = header(6)
        at = 6 + n
        do i = 1, len(name)
            name(i:i) = achar(header(at + i))
        end do
        at = at + len(name)
        do i = 1, len(formulation)
            formulation(i:i) = achar(header(at + i))
        end do
        call this%init(name, formulation, nn, ns, max(n, 1), nb)
        this%n_stored = n
        this%newton_iterations(1:n) = header(7:6 + n)
        at = 0
        call take(this%mesh)
        call take(this%stress_mesh)
        call take(this%time(1:n))
        this%position(:, :, 1:n) = reshape(next(3 * nn * n), [3, nn, n])
        this%directors(:, :, :, 1:n) = reshape(next(9 * nn * n), [3, 3, nn, n])
        this%velocity(:, :, 1:n) = reshape(next(3 * nn * n), [3, nn, n])
        this%director_velocity(:, :, :, 1:n) = reshape(next(9 * nn * n), [3, 3, nn, n])
        this%stress(:, :, 1:n) = reshape(next(6 * ns * n), [6, ns, n])
        this%strains(:, :, 1:n) = reshape(next(6 * ns * n), [6, ns, n])
        if (nb > 0) this%branch_stress(:, :, :, 1:n) = reshape(next(6 * ns * nb * n), &
            [6, ns, nb, n])
        call take(this%kinetic(1:n))
        call take(this%strain(1:n))
        call take(this%total(1:n))
        call take(this%external_work(1:n))
        call take(this%balance_error(1:n))
        call take(this%dissipated(1:n))
        call take(this%actuator_work(1:n))
        this%linear_momentum(:, 1:n) = reshape(next(3 * n), [3, n])
        this%angular_momentum(:, 1:n) = reshape(next(3 * n), [3, n])
        this%center_of_mass(:, 1:n) = reshape(next(3 * n), [3, n])
        call take(this%constraint_residual(1:n))
        call take(this%newton_residual(1:n))
        call take(this%dt(1:n))
    contains
        subroutine take(target)
            real(rk), intent(out) :: target(:)
            target = values(at + 1 : at + size(target))
            at = at + size(target)
        end subroutine take
        function next(count) result(chunk)
            integer, intent(in) :: count
            real(rk) :: chunk(count)
            chunk = values(at + 1 : at + count)
            at = at + count
        end function next
    end subroutine rod_history_unpack

end module rs_model_rod_history
