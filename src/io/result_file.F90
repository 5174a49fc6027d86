!> The result file of a run (DESIGN.md §7, schema version 1), written from plain data: run
!> metadata (`result_meta_t`) and the stored records of each rod (`rod_history_t`). One rank
!> writes (the caller gathers to rank 0); see docs/user/output.md for the schema as built.
!>
!>     /                       attributes schema_version, creator, created, command_line,
!>                             n_ranks, petsc_version, hdf5_version, mpi_version, title
!>     /input/                 text, resolved, petsc_options
!>     /rods/<name>/           attribute formulation; mesh, stress_mesh, time, position,
!>                             directors, velocity, director_velocity, stress, strain,
!>                             branch_stress (rods with Maxwell branches only)
!>     /rods/<name>/series/    energy/{kinetic,strain,total,external_work,actuator_work,
!>                             dissipated,balance_error},
!>                             momentum/{linear,angular}, center_of_mass,
!>                             constraint_residual, newton/{iterations,residual}, dt
!>     /series/                time, energy/..., momentum/... summed over all rods
!>
!> Arrays are written in Fortran order, so h5py shows them reversed: position(:, node, step) is
!> h5py's position[step, node, :]. A formulation that leaves an array unallocated or of size
!> zero gets no dataset for it; the sums in /series/ cover the quantities every rod has.
module rs_io_result_file
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: str
    use rs_core_version, only: rodsolve_version, rodsolve_git_commit
    use rs_model_rod_history, only: rod_history_t
    use rs_io_hdf5_file, only: hdf5_file_t
    use rs_io_hdf5_info, only: hdf5_version
    implicit none
    private

    public :: result_meta_t, write_result_file

    !> Version of the layout written by this module; readers check it.
    integer, parameter, public :: result_schema_version = 1

    !> What a result file records about the run besides the rods. Unallocated strings are
    !> written as empty strings. The HDF5 version is the writer's own (rs_io_hdf5_info).
    type, public :: result_meta_t
        !> The scene's title (&run title).
        character(len=:), allocatable :: title
        !> The command line of the run, program name included.
        character(len=:), allocatable :: command_line
        !> Number of MPI ranks of the run.
        integer :: n_ranks = 1
        !> PETSc's version string.
        character(len=:), allocatable :: petsc_version
        !> The MPI library's version string.
        character(len=:), allocatable :: mpi_version
        !> The scene file, verbatim.
        character(len=:), allocatable :: input_text
        !> The resolved scene (defaults and derived values included) as namelist text.
        character(len=:), allocatable :: input_resolved
        !> The PETSc options in use, as option text.
        character(len=:), allocatable :: petsc_options
    end type result_meta_t

    character(len=*), parameter :: energy_names(7) = [character(len=13) :: 'kinetic', &
        'strain', 'total', 'external_work', 'actuator_work', 'dissipated', 'balance_error']
    character(len=*), parameter :: momentum_names(2) = [character(len=7) :: 'linear', 'angular']
    !> Unit and components attribute of `stress` and `branch_stress`.
    character(len=*), parameter :: stress_unit = 'N (N1, N2, N3); N m (M1, M2, M3)'
    character(len=*), parameter :: stress_components = 'N1 N2 N3 M1 M2 M3'

contains

    !> Write the result file `path` (replacing an existing one; missing directories are
    !> created): `meta` and the first `n_stored` records of each history. All rods must share
    !> the time grid of their stored records. The histories are checked before the file is
    !> created, so an inconsistent history leaves no file behind.
    subroutine write_result_file(path, meta, histories, err)
        character(len=*), intent(in) :: path
        type(result_meta_t), intent(in) :: meta
        type(rod_history_t), intent(in) :: histories(:)
        type(error_t), allocatable, intent(out) :: err
        type(hdf5_file_t) :: file
        type(error_t), allocatable :: close_err
        integer :: i

        call check_histories(histories, err)
        if (allocated(err)) then
            err%message = 'cannot write "' // path // '": ' // err%message
            return
        end if
        call file%create(path, err)
        if (allocated(err)) return
        call write_root(file, meta, err)
        call write_input(file, meta, err)
        do i = 1, size(histories)
            call write_rod(file, histories(i), err)
        end do
        call write_root_series(file, histories, err)
        call file%close(close_err)
        if (.not. allocated(err) .and. allocated(close_err)) call move_alloc(close_err, err)
    end subroutine write_result_file

    !> Rod names usable as group names and unique; each stored array holds `n_stored` records;
    !> one time grid for all rods.
    subroutine check_histories(histories, err)
        type(rod_history_t), intent(in) :: histories(:)
        type(error_t), allocatable, intent(out) :: err
        character(len=*), parameter :: routine = 'write_result_file'
        character(len=:), allocatable :: name
        real(rk) :: tolerance
        integer :: i, j, n

        if (size(histories) == 0) then
            call set_error(err, 'no rod histories given', routine, __FILE__, __LINE__)
            return
        end if
        do i = 1, size(histories)
            name = ''
            if (allocated(histories(i)%name)) name = histories(i)%name
            if (len(name) == 0 .or. name == '.' .or. name == '..' .or. index(name, '/') > 0) then
                call set_error(err, 'rod ' // str(i) // ' has the name "' // name // &
                    '", which cannot name an HDF5 group (empty, "/", "." or "..")', routine, &
                    __FILE__, __LINE__)
                return
            end if
            do j = 1, i - 1
                if (histories(j)%name == name) then
                    call set_error(err, 'two rods are named "' // name // '"', routine, &
                        __FILE__, __LINE__)
                    return
                end if
            end do
            call check_record_counts(histories(i), err)
            if (allocated(err)) return
        end do

        n = histories(1)%n_stored
        ! Rods stepped apart may add up their times in different orders.
        tolerance = 0.0_rk
        if (n > 0) tolerance = 1.0e-12_rk * maxval(abs(histories(1)%time(1:n)))
        do i = 2, size(histories)
            if (histories(i)%n_stored /= n) then
                call set_error(err, 'rods "' // histories(1)%name // '" and "' // &
                    histories(i)%name // '" do not share the time grid: ' // str(n) // &
                    ' and ' // str(histories(i)%n_stored) // ' stored records', routine, &
                    __FILE__, __LINE__)
                return
            end if
            do j = 1, n
                if (abs(histories(i)%time(j) - histories(1)%time(j)) > tolerance) then
                    call set_error(err, 'rods "' // histories(1)%name // '" and "' // &
                        histories(i)%name // '" do not share the time grid: record ' // &
                        str(j) // ' is at time ' // str(histories(1)%time(j)) // ' and ' // &
                        str(histories(i)%time(j)), routine, __FILE__, __LINE__)
                    return
                end if
            end do
        end do
    end subroutine check_histories

    !> Every stored-step array that is present holds at least `n_stored` records, and `time`
    !> is present.
    subroutine check_record_counts(h, err)
        type(rod_history_t), intent(in) :: h
        type(error_t), allocatable, intent(out) :: err
        integer :: k
        character(len=:), allocatable :: what
        real(rk), allocatable :: values_1(:), values_2(:, :)
        if (h%n_stored < 0) then
            what = 'n_stored'
        else if (.not. allocated(h%time)) then
            what = 'time (not allocated)'
        else if (size(h%time) < h%n_stored) then
            what = 'time'
        else if (.not. allocated(h%formulation)) then
            what = 'formulation (not set)'
        else
            what = ''
            if (too_short_3(h%position, h%n_stored)) what = 'position'
            if (too_short_4(h%directors, h%n_stored)) what = 'directors'
            if (too_short_3(h%velocity, h%n_stored)) what = 'velocity'
            if (too_short_4(h%director_velocity, h%n_stored)) what = 'director_velocity'
            if (too_short_3(h%stress, h%n_stored)) what = 'stress'
            if (too_short_3(h%strains, h%n_stored)) what = 'strains'
            if (too_short_4(h%branch_stress, h%n_stored)) what = 'branch_stress'
            do k = 1, size(energy_names)
                call energy_of(h, energy_names(k), values_1)
                if (too_short_1(values_1, h%n_stored)) what = trim(energy_names(k))
            end do
            do k = 1, size(momentum_names)
                call momentum_of(h, momentum_names(k), values_2)
                if (too_short_2(values_2, h%n_stored)) &
                    what = trim(momentum_names(k)) // '_momentum'
            end do
            if (too_short_2(h%center_of_mass, h%n_stored)) what = 'center_of_mass'
            if (too_short_1(h%constraint_residual, h%n_stored)) what = 'constraint_residual'
            if (too_short_1(h%newton_residual, h%n_stored)) what = 'newton_residual'
            if (too_short_1(h%dt, h%n_stored)) what = 'dt'
            if (allocated(h%newton_iterations)) then
                if (size(h%newton_iterations) > 0 .and. size(h%newton_iterations) < h%n_stored) &
                    what = 'newton_iterations'
            end if
            if (len(what) == 0) return
        end if
        call set_error(err, 'the history of rod "' // h%name // '" is inconsistent: ' // what // &
            ' holds fewer records than n_stored = ' // str(h%n_stored), 'write_result_file', &
            __FILE__, __LINE__)
    end subroutine check_record_counts

    subroutine write_root(file, meta, err)
        type(hdf5_file_t), intent(inout) :: file
        type(result_meta_t), intent(in) :: meta
        type(error_t), allocatable, intent(inout) :: err
        call put_attribute_int(file, '/', 'schema_version', result_schema_version, err)
        call put_attribute(file, '/', 'creator', 'rodsolve ' // rodsolve_version // ' (git ' // &
            rodsolve_git_commit // ')', err)
        call put_attribute(file, '/', 'created', iso_8601_now(), err)
        call put_attribute(file, '/', 'command_line', text_of(meta%command_line), err)
        call put_attribute_int(file, '/', 'n_ranks', meta%n_ranks, err)
        call put_attribute(file, '/', 'petsc_version', text_of(meta%petsc_version), err)
        call put_attribute(file, '/', 'hdf5_version', hdf5_version(), err)
        call put_attribute(file, '/', 'mpi_version', text_of(meta%mpi_version), err)
        call put_attribute(file, '/', 'title', text_of(meta%title), err)
    end subroutine write_root

    subroutine write_input(file, meta, err)
        type(hdf5_file_t), intent(inout) :: file
        type(result_meta_t), intent(in) :: meta
        type(error_t), allocatable, intent(inout) :: err
        if (allocated(err)) return
        call file%write_string_dataset('/input/text', text_of(meta%input_text), &
            'the scene file as given, verbatim', err)
        if (allocated(err)) return
        call file%write_string_dataset('/input/resolved', text_of(meta%input_resolved), &
            'the resolved scene as namelist text: every group and variable, defaults and ' // &
            'derived values included; rodsolve reads it back to the same scene (DESIGN.md §6)', &
            err)
        if (allocated(err)) return
        call file%write_string_dataset('/input/petsc_options', text_of(meta%petsc_options), &
            'the PETSc options in use: scene values, then the scene''s petsc_options, then ' // &
            'the command line, later ones winning (DESIGN.md §3)', err)
    end subroutine write_input

    !> /rods/<name>/ with the rod's fields and /rods/<name>/series/.
    subroutine write_rod(file, h, err)
        type(hdf5_file_t), intent(inout) :: file
        type(rod_history_t), intent(in) :: h
        type(error_t), allocatable, intent(inout) :: err
        character(len=:), allocatable :: group, series
        real(rk), allocatable :: values_1(:), values_2(:, :)
        integer :: n, k

        if (allocated(err)) return
        n = h%n_stored
        group = '/rods/' // h%name
        series = group // '/series'
        call file%create_group(group, err)
        if (allocated(err)) return
        call put_attribute(file, group, 'formulation', h%formulation, err)

        call put_mesh(file, group // '/mesh', h%mesh, &
            'reference arc length s of the nodes, [node]', err)
        call put_mesh(file, group // '/stress_mesh', h%stress_mesh, &
            'reference arc length of the stress points (the element stress coefficients, ' // &
            'element by element), [point]', err)
        call put_1(file, group // '/time', h%time, n, 's', 'time of each stored record, [step]', &
            err)
        call put_3(file, group // '/position', h%position, n, 'm', &
            'centreline position phi of the nodes in the spatial frame, [step, node, component]', &
            err)
        call put_4(file, group // '/directors', h%directors, n, '1', &
            'directors of the nodes: [step, node, i, :] holds the spatial components of ' // &
            'd_(i+1) (h5py index i = 0, 1, 2 for d1, d2, d3)', err)
        call put_3(file, group // '/velocity', h%velocity, n, 'm/s', &
            'centreline velocity of the nodes in the spatial frame, [step, node, component]', &
            err)
        call put_4(file, group // '/director_velocity', h%director_velocity, n, '1/s', &
            'time derivative of the directors: [step, node, i, :] holds the spatial ' // &
            'components of d(d_(i+1))/dt', err)
        call put_3(file, group // '/stress', h%stress, n, stress_unit, &
            'total stress resultants (elastic branch plus all Maxwell branches) at the ' // &
            'stress points in material (director) components, [step, point, k] with k over ' // &
            'the attribute components: forces N and moments M; stress minus the sum of ' // &
            'branch_stress over the branches is the elastic-branch stress', err, &
            stress_components)
        call put_3(file, group // '/strain', h%strains, n, '1 (Gamma); 1/m (K)', &
            'strains computed from the displacements at the stress points (straight ' // &
            'reference: Gamma0 = (0, 0, 1), K0 = 0); strain consistency: C sigma_elastic = ' // &
            'strain - strain0 (methods/ph_director_3d.md §2.2, §5.3 item 3), ' // &
            '[step, point, k] with k over the attribute components', err, &
            'Gamma1 Gamma2 Gamma3 K1 K2 K3')
        call put_4(file, group // '/branch_stress', h%branch_stress, n, stress_unit, &
            'stress resultants of the generalized-Maxwell branches at the stress points in ' // &
            'material (director) components, [step, branch, point, k] with k over the ' // &
            'attribute components (methods/ph_director_3d.md §3.1); stress minus their sum ' // &
            'over the branches is the elastic-branch stress', err, stress_components)

        do k = 1, size(energy_names)
            call energy_of(h, energy_names(k), values_1)
            call put_1(file, series // '/energy/' // trim(energy_names(k)), values_1, n, 'J', &
                energy_description(energy_names(k)), err)
        end do
        do k = 1, size(momentum_names)
            call momentum_of(h, momentum_names(k), values_2)
            call put_2(file, series // '/momentum/' // trim(momentum_names(k)), values_2, n, &
                momentum_unit(momentum_names(k)), momentum_description(momentum_names(k)), err)
        end do
        call put_2(file, series // '/center_of_mass', h%center_of_mass, n, 'm', &
            'centre of mass of the centreline (1/L) int phi ds, [step, component]', err)
        call put_1(file, series // '/constraint_residual', h%constraint_residual, n, '1', &
            'largest nodal orthonormality residual max_k |g(d_k)| (d_i . d_j - delta_ij) at ' // &
            'the record, [step]', err)
        if (allocated(h%newton_iterations) .and. .not. allocated(err)) then
            if (size(h%newton_iterations) > 0) call file%write_dataset( &
                series // '/newton/iterations', h%newton_iterations(1:n), '1', &
                'Newton iterations of the step that ended at this record, [step]', err, &
                series=.true.)
        end if
        call put_1(file, series // '/newton/residual', h%newton_residual, n, &
            'as newton_atol', 'final Newton residual norm of the step that ended at this ' // &
            'record, in the row scaling of the formulation''s method document ' // &
            '(DESIGN.md §3), [step]', err)
        call put_1(file, series // '/dt', h%dt, n, 's', 'time step that ended at this ' // &
            'record (after cut-backs, the smallest substep), [step]', err)
    end subroutine write_rod

    !> /series/: the time grid and the energies and momenta summed over the rods (each sum only
    !> when every rod has the quantity).
    subroutine write_root_series(file, histories, err)
        type(hdf5_file_t), intent(inout) :: file
        type(rod_history_t), intent(in) :: histories(:)
        type(error_t), allocatable, intent(inout) :: err
        real(rk), allocatable :: sum_1(:), sum_2(:, :), values_1(:), values_2(:, :)
        integer :: n, i, k
        logical :: everywhere

        n = histories(1)%n_stored
        call put_1(file, '/series/time', histories(1)%time, n, 's', &
            'time of each stored record, shared by all rods, [step]', err)
        do k = 1, size(energy_names)
            everywhere = .true.
            allocate(sum_1(n), source=0.0_rk)
            do i = 1, size(histories)
                call energy_of(histories(i), energy_names(k), values_1)
                everywhere = everywhere .and. has_1(values_1)
                if (everywhere) sum_1 = sum_1 + values_1(1:n)
            end do
            if (everywhere) call put_1(file, '/series/energy/' // trim(energy_names(k)), sum_1, &
                n, 'J', 'sum over all rods: ' // energy_description(energy_names(k)), err)
            deallocate(sum_1)
        end do
        do k = 1, size(momentum_names)
            everywhere = .true.
            allocate(sum_2(3, n), source=0.0_rk)
            do i = 1, size(histories)
                call momentum_of(histories(i), momentum_names(k), values_2)
                everywhere = everywhere .and. has_2(values_2)
                if (everywhere) sum_2 = sum_2 + values_2(:, 1:n)
            end do
            if (everywhere) call put_2(file, '/series/momentum/' // trim(momentum_names(k)), &
                sum_2, n, momentum_unit(momentum_names(k)), 'sum over all rods: ' // &
                momentum_description(momentum_names(k)), err)
            deallocate(sum_2)
        end do
    end subroutine write_root_series

    !> A copy of the energy series `name` of `h`; unallocated when the rod does not have it.
    pure subroutine energy_of(h, name, values)
        type(rod_history_t), intent(in) :: h
        character(len=*), intent(in) :: name
        real(rk), allocatable, intent(out) :: values(:)
        select case (name)
        case ('kinetic')
            if (allocated(h%kinetic)) values = h%kinetic
        case ('strain')
            if (allocated(h%strain)) values = h%strain
        case ('total')
            if (allocated(h%total)) values = h%total
        case ('external_work')
            if (allocated(h%external_work)) values = h%external_work
        case ('actuator_work')
            if (allocated(h%actuator_work)) values = h%actuator_work
        case ('dissipated')
            if (allocated(h%dissipated)) values = h%dissipated
        case ('balance_error')
            if (allocated(h%balance_error)) values = h%balance_error
        end select
    end subroutine energy_of

    !> A copy of the momentum series `name` ('linear' or 'angular') of `h`, (3, records);
    !> unallocated when the rod does not have it.
    pure subroutine momentum_of(h, name, values)
        type(rod_history_t), intent(in) :: h
        character(len=*), intent(in) :: name
        real(rk), allocatable, intent(out) :: values(:, :)
        select case (name)
        case ('linear')
            if (allocated(h%linear_momentum)) values = h%linear_momentum
        case ('angular')
            if (allocated(h%angular_momentum)) values = h%angular_momentum
        end select
    end subroutine momentum_of

    pure function energy_description(name) result(text)
        character(len=*), intent(in) :: name
        character(len=:), allocatable :: text
        select case (name)
        case ('kinetic')
            text = 'kinetic energy at the record, [step]'
        case ('strain')
            text = 'strain energy at the record (in mixed formulations the complementary ' // &
                'energy of the stresses), [step]'
        case ('total')
            text = 'total energy H (the Hamiltonian of the formulation) at the record, [step]'
        case ('external_work')
            text = 'work W_ext of the external loads summed over the steps since the ' // &
                'previous record (its cumulative sum is the work done since the start), [step]'
        case ('actuator_work')
            text = 'work of the pneumatic and tendon actuators, W_act = -h int Delta ' // &
                'sigma_act . eps_dot(q_mid, v_mid) ds, summed over the steps since the ' // &
                'previous record (methods/ph_director_3d.md §3.2), [step]'
        case ('dissipated')
            text = 'energy dissipated by the Maxwell branches, D_n = h sum_i int ' // &
                'sigma_mid^(i) . V^(i)^-1 sigma_mid^(i) ds >= 0, summed over the steps since ' // &
                'the previous record (methods/ph_director_3d.md §3.1, §5.3), [step]'
        case ('balance_error')
            text = 'energy-balance error H_{n+1} - H_n - W_ext - W_act + D summed over the ' // &
                'steps since the previous record (methods/ph_director_3d.md §5.3, §3.1; §9 ' // &
                'item 7 for the sign of D), [step]'
        case default
            text = name
        end select
    end function energy_description

    pure function momentum_unit(name) result(text)
        character(len=*), intent(in) :: name
        character(len=:), allocatable :: text
        if (name == 'linear') then
            text = 'kg m/s'
        else
            text = 'kg m^2/s'
        end if
    end function momentum_unit

    pure function momentum_description(name) result(text)
        character(len=*), intent(in) :: name
        character(len=:), allocatable :: text
        if (name == 'linear') then
            text = 'total linear momentum int rhoA v ds in the spatial frame, [step, component]'
        else
            text = 'total angular momentum about the spatial origin ' // &
                '(methods/ph_director_3d.md §5.3 item 4), [step, component]'
        end if
    end function momentum_description

    ! The put_* helpers do nothing once `err` is set, so a sequence of writes needs one check
    ! at its end; absent arrays (unallocated or of size zero) are skipped.

    subroutine put_attribute(file, object, name, value, err)
        type(hdf5_file_t), intent(inout) :: file
        character(len=*), intent(in) :: object, name, value
        type(error_t), allocatable, intent(inout) :: err
        if (allocated(err)) return
        call file%write_attribute(object, name, value, err)
    end subroutine put_attribute

    subroutine put_attribute_int(file, object, name, value, err)
        type(hdf5_file_t), intent(inout) :: file
        character(len=*), intent(in) :: object, name
        integer, intent(in) :: value
        type(error_t), allocatable, intent(inout) :: err
        if (allocated(err)) return
        call file%write_attribute(object, name, value, err)
    end subroutine put_attribute_int

    subroutine put_mesh(file, path, values, description, err)
        type(hdf5_file_t), intent(inout) :: file
        character(len=*), intent(in) :: path, description
        real(rk), allocatable, intent(in) :: values(:)
        type(error_t), allocatable, intent(inout) :: err
        if (allocated(err) .or. .not. has_1(values)) return
        call file%write_dataset(path, values, 'm', description, err)
    end subroutine put_mesh

    subroutine put_1(file, path, values, n, unit, description, err)
        type(hdf5_file_t), intent(inout) :: file
        character(len=*), intent(in) :: path, unit, description
        real(rk), allocatable, intent(in) :: values(:)
        integer, intent(in) :: n
        type(error_t), allocatable, intent(inout) :: err
        if (allocated(err) .or. .not. has_1(values)) return
        call file%write_dataset(path, values(1:n), unit, description, err, series=.true.)
    end subroutine put_1

    subroutine put_2(file, path, values, n, unit, description, err)
        type(hdf5_file_t), intent(inout) :: file
        character(len=*), intent(in) :: path, unit, description
        real(rk), allocatable, intent(in) :: values(:, :)
        integer, intent(in) :: n
        type(error_t), allocatable, intent(inout) :: err
        if (allocated(err) .or. .not. has_2(values)) return
        call file%write_dataset(path, values(:, 1:n), unit, description, err, series=.true.)
    end subroutine put_2

    ! put_3 and put_4 also write the attribute `components` when it is given.

    subroutine put_3(file, path, values, n, unit, description, err, components)
        type(hdf5_file_t), intent(inout) :: file
        character(len=*), intent(in) :: path, unit, description
        real(rk), allocatable, intent(in) :: values(:, :, :)
        integer, intent(in) :: n
        type(error_t), allocatable, intent(inout) :: err
        character(len=*), intent(in), optional :: components
        if (allocated(err) .or. .not. has_3(values)) return
        call file%write_dataset(path, values(:, :, 1:n), unit, description, err, series=.true.)
        if (present(components)) call put_attribute(file, path, 'components', components, err)
    end subroutine put_3

    subroutine put_4(file, path, values, n, unit, description, err, components)
        type(hdf5_file_t), intent(inout) :: file
        character(len=*), intent(in) :: path, unit, description
        real(rk), allocatable, intent(in) :: values(:, :, :, :)
        integer, intent(in) :: n
        type(error_t), allocatable, intent(inout) :: err
        character(len=*), intent(in), optional :: components
        if (allocated(err)) return
        if (.not. allocated(values)) return
        if (size(values) == 0) return
        call file%write_dataset(path, values(:, :, :, 1:n), unit, description, err, &
            series=.true.)
        if (present(components)) call put_attribute(file, path, 'components', components, err)
    end subroutine put_4

    pure logical function has_1(values)
        real(rk), allocatable, intent(in) :: values(:)
        has_1 = .false.
        if (allocated(values)) has_1 = size(values) > 0
    end function has_1

    pure logical function has_2(values)
        real(rk), allocatable, intent(in) :: values(:, :)
        has_2 = .false.
        if (allocated(values)) has_2 = size(values) > 0
    end function has_2

    pure logical function has_3(values)
        real(rk), allocatable, intent(in) :: values(:, :, :)
        has_3 = .false.
        if (allocated(values)) has_3 = size(values) > 0
    end function has_3

    ! A present array (allocated, not empty) with fewer than n records in its last dimension.

    pure logical function too_short_1(values, n)
        real(rk), allocatable, intent(in) :: values(:)
        integer, intent(in) :: n
        too_short_1 = .false.
        if (has_1(values)) too_short_1 = size(values) < n
    end function too_short_1

    pure logical function too_short_2(values, n)
        real(rk), allocatable, intent(in) :: values(:, :)
        integer, intent(in) :: n
        too_short_2 = .false.
        if (has_2(values)) too_short_2 = size(values, 2) < n
    end function too_short_2

    pure logical function too_short_3(values, n)
        real(rk), allocatable, intent(in) :: values(:, :, :)
        integer, intent(in) :: n
        too_short_3 = .false.
        if (has_3(values)) too_short_3 = size(values, 3) < n
    end function too_short_3

    pure logical function too_short_4(values, n)
        real(rk), allocatable, intent(in) :: values(:, :, :, :)
        integer, intent(in) :: n
        too_short_4 = .false.
        if (.not. allocated(values)) return
        if (size(values) > 0) too_short_4 = size(values, 4) < n
    end function too_short_4

    pure function text_of(text) result(out)
        character(len=:), allocatable, intent(in) :: text
        character(len=:), allocatable :: out
        if (allocated(text)) then
            out = text
        else
            out = ''
        end if
    end function text_of

    !> Local time as ISO 8601, e.g. 2024-05-01T14:03:59+02:00 (no offset when unknown).
    function iso_8601_now() result(text)
        character(len=:), allocatable :: text
        integer :: v(8), offset
        character(len=32) :: buffer
        character :: sign
        call date_and_time(values=v)
        write(buffer, '(i4.4, "-", i2.2, "-", i2.2, "T", i2.2, ":", i2.2, ":", i2.2)') &
            v(1), v(2), v(3), v(5), v(6), v(7)
        text = trim(buffer)
        if (v(4) == -huge(v(4))) return
        offset = abs(v(4))
        sign = '+'
        if (v(4) < 0) sign = '-'
        write(buffer, '(a1, i2.2, ":", i2.2)') sign, offset / 60, mod(offset, 60)
        text = text // trim(buffer)
    end function iso_8601_now

end module rs_io_result_file
