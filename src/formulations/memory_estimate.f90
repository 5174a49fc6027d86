!> The memory a run of a scene will need (issue 21 item 17), from the sizes of its rods
!> (rs_formulations_rod_sizes: Jacobian non-zeros, unknowns, state), so that --check-input
!> prints it and a run that will not fit is refused before anything is allocated.
!>
!> Model of one rank's peak resident memory (docs/user/getting_started.md, "Memory"):
!>
!>     rank_baseline + sum over the rank's rods of
!>         bytes_per_nonzero * nnz + bytes_per_unknown * unknowns + history
!>
!> - rank_baseline: PETSc, MPI and HDF5 loaded, a small scene read (measured: 60-65 MB).
!> - bytes_per_nonzero covers what grows with the Jacobian: its CSR values and indices in the
!>   formulation and in PETSc's matrix (12 + 12 bytes), the scatter of the element and node
!>   kernels into it, and the LU factor with its fill. Measured on single rods, 2 steps, 1 rank
!>   (2026-11-26, /usr/bin/time peak RSS at 1000 and 4000 elements, the slope less the
!>   unknowns and records): ph_director 73, ph_planar 79, se3_strand 54, se3_pg 89,
!>   cl_em_planar 156 bytes per non-zero (its Jacobian is small, its factor fills more). 96
!>   is taken: within a factor 2 of each, above all but the smallest, since refusing a run that
!>   would have fitted is the smaller harm (tests/input/big_scenes.py checks the estimate
!>   against measured runs).
!> - bytes_per_unknown: the Newton vectors (solution, residual, update, line search, the
!>   state at t_n and t_n+1: about 12 vectors of 8 bytes).
!> - history: the records kept between two flushes, at most flush_every / stride + 4 (as
!>   run_scene sizes them) and at most the run's records, each about 8 bytes per entry of the
!>   state (positions, directors, velocities, stresses, strains).
!> A bundle solved by all ranks together (DESIGN.md §5) is split evenly among them.
module rs_formulations_memory_estimate
    use, intrinsic :: iso_fortran_env, only: int64
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t
    use rs_core_strings, only: str
    use rs_model_scene, only: scene_t, step_count
    use rs_model_coupling, only: coupled_systems, system_costs
    use rs_formulations_registry, only: is_bundle
    use rs_parallel_deal, only: deal_by_cost
    use rs_formulations_rod_sizes, only: rod_sizes_t, rod_sizes_of
    use rs_formulations_formulation, only: rod_formulation_t
    use rs_formulations_factory, only: create_formulation
    implicit none
    private

    public :: run_memory_estimate, rod_memory_bytes, memory_refusal, available_memory_bytes, &
        bytes_text

    real(rk), parameter, public :: rank_baseline_bytes = 64.0e6_rk
    real(rk), parameter, public :: bytes_per_nonzero = 96.0_rk
    real(rk), parameter, public :: bytes_per_unknown = 96.0_rk
    real(rk), parameter, public :: bytes_per_state_entry = 8.0_rk

    !> The estimate of a run: its peak on the busiest rank and over all ranks together.
    type, public :: memory_estimate_t
        !> False if a rod could not be sized (its formulation cannot build it): no estimate.
        logical :: known = .false.
        real(rk) :: busiest_rank_bytes = 0.0_rk
        integer :: busiest_rank = 0
        real(rk) :: total_bytes = 0.0_rk
        !> The rod with the largest share, and that share.
        integer :: largest_rod = 0
        real(rk) :: largest_rod_bytes = 0.0_rk
    end type memory_estimate_t

contains

    !> The memory estimate of a run of `scene` on `n_ranks` ranks, rods dealt as run_scene
    !> deals them.
    function run_memory_estimate(scene, n_ranks) result(estimate)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: n_ranks
        type(memory_estimate_t) :: estimate
        type(rod_sizes_t) :: sizes
        type(error_t), allocatable :: err
        class(rod_formulation_t), allocatable :: mold
        integer, allocatable :: system_of(:), first(:), members(:), system_rank(:)
        real(rk), allocatable :: rank_bytes(:)
        real(rk) :: bytes
        integer :: i, s
        call coupled_systems(scene, system_of, first, members)
        system_rank = deal_by_cost(system_costs(scene, first, members), n_ranks)
        allocate(rank_bytes(0:max(n_ranks, 1) - 1), source=rank_baseline_bytes)
        do i = 1, size(scene%rods)
            call create_formulation(trim(scene%rods(i)%formulation), mold, err)
            if (allocated(err)) return
            call rod_sizes_of(scene, i, sizes, err, mold)
            if (allocated(err)) return
            bytes = rod_memory_bytes(scene, sizes)
            if (bytes > estimate%largest_rod_bytes) then
                estimate%largest_rod = i
                estimate%largest_rod_bytes = bytes
            end if
            s = system_of(i)
            if (n_ranks > 1 .and. is_bundle(scene, members(first(s):first(s + 1) - 1))) then
                rank_bytes = rank_bytes + bytes / real(n_ranks, rk)
            else
                rank_bytes(system_rank(s)) = rank_bytes(system_rank(s)) + bytes
            end if
        end do
        estimate%known = .true.
        estimate%busiest_rank = maxloc(rank_bytes, 1) - 1
        estimate%busiest_rank_bytes = maxval(rank_bytes)
        estimate%total_bytes = sum(rank_bytes)
    end function run_memory_estimate

    !> Peak bytes of one rod of `scene` with `sizes` (the model of the module header).
    pure real(rk) function rod_memory_bytes(scene, sizes) result(bytes)
        type(scene_t), intent(in) :: scene
        type(rod_sizes_t), intent(in) :: sizes
        integer(int64) :: n_records, kept
        n_records = 2 + step_count(scene) / max(scene%output%stride, 1)
        kept = min(n_records, int(scene%output%flush_every / max(scene%output%stride, 1) + 4, &
            int64))
        bytes = bytes_per_nonzero * real(sizes%n_nonzeros, rk) + &
            bytes_per_unknown * real(sizes%n_unknown, rk) + &
            bytes_per_state_entry * real(kept, rk) * real(sizes%n_state, rk)
    end function rod_memory_bytes

    !> '' if the run fits, else why it is refused: the busiest rank's estimate against the
    !> memory available to it, MemAvailable of /proc/meminfo shared by the ranks of this machine
    !> (OMPI_COMM_WORLD_LOCAL_SIZE or MPI_LOCALNRANKS, else 1), or the limit in bytes of the
    !> environment variable RODSOLVE_MEMORY_LIMIT per rank when set. Every rank computes the
    !> same verdict from the same scene. Nothing is refused when nothing is known.
    function memory_refusal(scene, n_ranks) result(message)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: n_ranks
        character(len=:), allocatable :: message
        type(memory_estimate_t) :: estimate
        character(len=:), allocatable :: source
        real(rk) :: per_rank
        message = ''
        call rank_memory_available(per_rank, source)
        if (per_rank <= 0.0_rk) return
        estimate = run_memory_estimate(scene, n_ranks)
        if (.not. estimate%known) return
        if (estimate%busiest_rank_bytes <= per_rank) return
        message = 'the run needs an estimated ' // bytes_text(estimate%busiest_rank_bytes) // &
            ' on rank ' // str(estimate%busiest_rank) // ' but ' // bytes_text(per_rank) // &
            ' are available to it (' // source // '); the largest part is rod ''' // &
            trim(scene%rods(estimate%largest_rod)%name) // ''' (' // &
            bytes_text(estimate%largest_rod_bytes) // ', ' // &
            str(scene%rods(estimate%largest_rod)%n_elements) // ' elements). Use fewer ' // &
            'elements or a smaller flush_every, or spread the rods over ranks on more ' // &
            'machines; the estimate is in the plan of rodsolve --check-input ' // &
            '(docs/user/getting_started.md, "Memory")'
    end function memory_refusal

    !> Bytes one rank may use and where that comes from; 0 if unknown.
    subroutine rank_memory_available(bytes, source)
        real(rk), intent(out) :: bytes
        character(len=:), allocatable, intent(out) :: source
        character(len=64) :: value
        integer :: length, status, ios, local_ranks
        real(rk) :: limit
        call get_environment_variable('RODSOLVE_MEMORY_LIMIT', value, length, status)
        if (status == 0 .and. length > 0) then
            read(value, *, iostat=ios) limit
            if (ios == 0 .and. limit > 0.0_rk) then
                bytes = limit
                source = 'RODSOLVE_MEMORY_LIMIT = ' // trim(value) // ' bytes per rank'
                return
            end if
        end if
        local_ranks = local_rank_count()
        bytes = available_memory_bytes() / real(local_ranks, rk)
        source = 'MemAvailable of /proc/meminfo'
        if (local_ranks > 1) source = source // ' shared by the ' // str(local_ranks) // &
            ' ranks of this machine'
    end subroutine rank_memory_available

    !> Ranks on this machine, as the MPI launcher tells them (1 if it does not).
    integer function local_rank_count() result(n)
        character(len=32) :: value
        integer :: status, ios
        character(len=*), parameter :: names(2) = [character(len=26) :: &
            'OMPI_COMM_WORLD_LOCAL_SIZE', 'MPI_LOCALNRANKS']
        integer :: k
        n = 1
        do k = 1, size(names)
            call get_environment_variable(trim(names(k)), value, status=status)
            if (status /= 0) cycle
            read(value, *, iostat=ios) n
            if (ios == 0 .and. n >= 1) return
            n = 1
        end do
    end function local_rank_count

    !> MemAvailable of /proc/meminfo in bytes; 0 if it cannot be read (not Linux).
    real(rk) function available_memory_bytes() result(bytes)
        character(len=256) :: line
        integer :: unit, ios
        real(rk) :: kilobytes
        bytes = 0.0_rk
        open(newunit=unit, file='/proc/meminfo', action='read', status='old', iostat=ios)
        if (ios /= 0) return
        do
            read(unit, '(a)', iostat=ios) line
            if (ios /= 0) exit
            if (index(line, 'MemAvailable:') /= 1) cycle
            read(line(len('MemAvailable:') + 1:), *, iostat=ios) kilobytes
            if (ios == 0) bytes = 1024.0_rk * kilobytes
            exit
        end do
        close(unit)
    end function available_memory_bytes

    !> "123 MB", "4.5 GB": bytes in words, two or three significant digits.
    function bytes_text(bytes) result(text)
        real(rk), intent(in) :: bytes
        character(len=:), allocatable :: text
        character(len=32) :: number
        if (bytes >= 1.0e12_rk) then
            write(number, '(f0.1)') bytes / 1.0e12_rk
            text = trim(number) // ' TB'
        else if (bytes >= 1.0e9_rk) then
            write(number, '(f0.1)') bytes / 1.0e9_rk
            text = trim(number) // ' GB'
        else
            write(number, '(i0)') nint(bytes / 1.0e6_rk)
            text = trim(number) // ' MB'
        end if
    end function bytes_text

end module rs_formulations_memory_estimate
