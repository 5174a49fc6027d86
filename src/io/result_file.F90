!> The result file of a run (DESIGN.md §7, schema version 2); docs/user/output.md documents it
!> field by field.
!>
!>     /                       attributes schema_version, creator, created, command_line,
!>                             n_ranks, petsc_version, hdf5_version, mpi_version, title,
!>                             status (at the end), restarted (after a restart)
!>     /input/                 text, resolved, petsc_options
!>     /rods/<name>/           attribute formulation; mesh, stress_mesh, time, and the selected
!>                             fields of position, directors, velocity, director_velocity,
!>                             stress, strain, branch_stress (rods with Maxwell branches)
!>     /rods/<name>/series/    energy/{kinetic,strain,total,external_work,actuator_work,
!>                             dissipated,balance_error}, momentum/{linear,angular},
!>                             center_of_mass, constraint_residual, newton/{iterations,residual},
!>                             dt; rods of a bundle: contact/{energy,force,penetration,
!>                             friction,slip_speed}, ties/{force,moment}
!>     /checkpoint/<name>/     state, ledger, step, records, time: what a restart needs;
!>                             checksum (rs_io_checksum), verified by read_checkpoint
!>     /series/                time, energy/..., momentum/... summed over all rods (at the end)
!>
!> A run writes the file in three stages: rank 0 creates it with every dataset empty
!> (`prepare_result_file`); every rank opens it (`result_writer_t`, parallel HDF5 when there are
!> several ranks) and at every flush disk space is reserved, the datasets are extended, each
!> rank writes the records of its own rods (collectively), the file is flushed, and then the
!> checkpoints are written and flushed, so a killed run leaves a readable file with every
!> record up to the last flush and a checkpoint that lists only records on disk; rank 0 finally
!> adds /series/ (`finish_result_file`). Growing datasets are chunked along the records, with
!> HDF5's Fletcher-32 checksum in a file one rank writes.
!>
!> Arrays are written in Fortran order, so h5py shows them reversed: position(:, node, step) is
!> h5py's position[step, node, :].
module rs_io_result_file
    use, intrinsic :: iso_fortran_env, only: int64
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: str
    use rs_core_version, only: rodsolve_version, rodsolve_git_commit
    use rs_model_rod_history, only: rod_history_t
    use hdf5, only: hsize_t
    use rs_io_hdf5_file, only: hdf5_file_t, series_chunk_records
    use rs_io_hdf5_info, only: hdf5_version
    use rs_io_checksum, only: checkpoint_checksum
    use rs_system_ledger, only: ledger_entries, ledger_entry_names
    use rs_model_units, only: unit_in_system
    implicit none
    private

    public :: result_meta_t, write_result_file, rod_layout_t, layout_of, pack_layout, unpack_layout
    public :: result_writer_t, prepare_result_file, finish_result_file, read_checkpoint
    public :: selectable_fields, unknown_fields, prepare_sweep_file

    !> Version of the layout written by this module; readers check it.
    integer, parameter, public :: result_schema_version = 2

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
        !> The scene's system of units (&run units); the `unit` attributes are written in it.
        character(len=:), allocatable :: units
    end type result_meta_t

    !> What the result file needs to know of a rod before its first record: the sizes that fix
    !> its datasets, the reference meshes, and the sizes of its checkpoint (the state vector and
    !> the record ledger's sums, rs_system_ledger).
    type, public :: rod_layout_t
        character(len=:), allocatable :: name
        character(len=:), allocatable :: formulation
        integer :: n_nodes = 0
        integer :: n_stress_points = 0
        integer :: n_branches = 0
        integer :: n_state = 0
        integer :: n_ledger = 0
        !> The rod whose checkpoint holds this rod's state (its index among the layouts), for the
        !> rods a joint couples to a system's first rod; 0: its own checkpoint.
        integer :: checkpoint_rod = 0
        real(rk), allocatable :: mesh(:)
        real(rk), allocatable :: stress_mesh(:)
        !> The fields the formulation records, as ',path,path,...,' (a formulation may leave
        !> an array of the history unallocated: it gets no dataset).
        character(len=:), allocatable :: recorded
    end type rod_layout_t

    !> One dataset of a rod that grows record by record, below /rods/<name>/.
    type :: field_t
        character(len=40) :: path = ''
        !> Fortran shape of one record (empty for a scalar per record).
        integer, allocatable :: dims(:)
        logical :: integer_values = .false.
        character(len=40) :: unit = ''
        character(len=:), allocatable :: description
        character(len=40) :: components = ''
    end type field_t

    type :: rod_fields_t
        type(field_t), allocatable :: list(:)
    end type rod_fields_t

    !> The result file during a run (DESIGN.md §7), open on every rank (with MPI-IO when there
    !> are several). At every flush, all collective: `extend` makes room for every rod's new
    !> records, `write_records` writes them (the owner of a rod passes its data, the others
    !> nothing) and `flush` puts them on disk; once every rank's flush succeeded,
    !> `commit_records` notes them as on disk, and `write_checkpoint` and another `flush`
    !> follow, so a checkpoint never lists records that are not in the file. When a write or
    !> flush failed on any rank (a full disk), `drop_unflushed` cuts the datasets back to the
    !> committed records (issue 21 item 3). Every collective procedure makes its HDF5 calls on
    !> every rank even after a local failure (the first error is returned), so that the ranks
    !> never wait for each other in different calls.
    type, public :: result_writer_t
        type(hdf5_file_t) :: file
        type(rod_layout_t), allocatable :: layouts(:)
        type(rod_fields_t), allocatable :: fields(:)
        !> Records of each rod in the file (after the last `extend`).
        integer, allocatable :: n_records(:)
        !> Records of each rod known to be on disk (after the last `commit_records`).
        integer, allocatable :: committed(:)
    contains
        procedure :: open => writer_open
        procedure :: extend => writer_extend
        procedure :: reserve => writer_reserve
        procedure :: write_records => writer_write_records
        procedure :: write_checkpoint => writer_write_checkpoint
        procedure :: flush => writer_flush
        procedure :: commit_records => writer_commit_records
        procedure :: drop_unflushed => writer_drop_unflushed
        procedure :: close => writer_close
        procedure, private :: set_all_records => writer_set_all_records
    end type result_writer_t

    !> The fields `&output fields` may select: nodal and stress fields, and the bundle series
    !> ('contact': the series/contact/ datasets, 'ties': series/ties/force and moment); the other
    !> per-record series and `time` are always written.
    character(len=*), parameter :: selectable_fields = &
        'position,directors,velocity,director_velocity,stress,strain,branch_stress,contact,ties'

    character(len=*), parameter :: energy_names(7) = [character(len=13) :: 'kinetic', &
        'strain', 'total', 'external_work', 'actuator_work', 'dissipated', 'balance_error']
    character(len=*), parameter :: momentum_names(2) = [character(len=7) :: 'linear', 'angular']
    character(len=*), parameter :: input_names(3) = [character(len=13) :: 'text', 'resolved', &
        'petsc_options']
    !> Unit and components attribute of `stress` and `branch_stress`.
    character(len=*), parameter :: stress_unit = 'N (N1, N2, N3); N m (M1, M2, M3)'
    character(len=*), parameter :: stress_components = 'N1 N2 N3 M1 M2 M3'

contains

    !> Write the whole result file `path` at once (replacing an existing one; missing
    !> directories are created): `meta` and the first `n_stored` records of each history. All
    !> rods must share the time grid of their stored records. The histories are checked before
    !> the file is created, so an inconsistent history leaves no file behind. (A run writes
    !> incrementally with prepare_result_file, result_writer_t and finish_result_file; this is
    !> the same sequence on one rank.)
    subroutine write_result_file(path, meta, histories, err)
        character(len=*), intent(in) :: path
        type(result_meta_t), intent(in) :: meta
        type(rod_history_t), intent(in) :: histories(:)
        type(error_t), allocatable, intent(out) :: err
        type(rod_layout_t), allocatable :: layouts(:)
        type(result_writer_t) :: writer
        type(error_t), allocatable :: close_err
        integer :: i

        call check_histories(histories, err)
        if (allocated(err)) then
            err%message = 'cannot write "' // path // '": ' // err%message
            return
        end if
        allocate(layouts(size(histories)))
        do i = 1, size(histories)
            layouts(i) = layout_of(histories(i), 0, 0)
        end do
        call prepare_result_file(path, meta, layouts, 'all', err)
        if (allocated(err)) return
        call writer%open(path, layouts, 'all', [(0, i = 1, size(layouts))], .false., err)
        if (allocated(err)) return
        call writer%extend([(histories(i)%n_stored, i = 1, size(histories))], err)
        do i = 1, size(histories)
            if (allocated(err)) exit
            call writer%write_records(i, err, histories(i))
        end do
        call writer%close(close_err)
        if (.not. allocated(err) .and. allocated(close_err)) call move_alloc(close_err, err)
        if (allocated(err)) return
        call finish_result_file(path, layouts, 'completed', err)
    end subroutine write_result_file

    !> The layout of a rod from its (initialized) history and its checkpoint sizes.
    function layout_of(h, n_state, n_ledger) result(layout)
        type(rod_history_t), intent(in) :: h
        integer, intent(in) :: n_state, n_ledger
        type(rod_layout_t) :: layout
        layout%name = h%name
        layout%formulation = h%formulation
        layout%n_nodes = h%n_nodes
        layout%n_stress_points = h%n_stress_points
        layout%n_branches = h%n_branches
        layout%n_state = n_state
        layout%n_ledger = n_ledger
        layout%mesh = h%mesh
        layout%stress_mesh = h%stress_mesh
        layout%recorded = ','
        if (allocated(h%time)) call note('time')
        if (has_3(h%position)) call note('position')
        if (has_4(h%directors)) call note('directors')
        if (has_3(h%velocity)) call note('velocity')
        if (has_4(h%director_velocity)) call note('director_velocity')
        if (has_3(h%stress)) call note('stress')
        if (has_3(h%strains)) call note('strain')
        if (has_4(h%branch_stress)) call note('branch_stress')
        if (has_1(h%kinetic)) call note('series/energy/kinetic')
        if (has_1(h%strain)) call note('series/energy/strain')
        if (has_1(h%total)) call note('series/energy/total')
        if (has_1(h%external_work)) call note('series/energy/external_work')
        if (has_1(h%actuator_work)) call note('series/energy/actuator_work')
        if (has_1(h%dissipated)) call note('series/energy/dissipated')
        if (has_1(h%balance_error)) call note('series/energy/balance_error')
        if (has_2(h%linear_momentum)) call note('series/momentum/linear')
        if (has_2(h%angular_momentum)) call note('series/momentum/angular')
        if (has_2(h%center_of_mass)) call note('series/center_of_mass')
        if (has_1(h%constraint_residual)) call note('series/constraint_residual')
        if (allocated(h%newton_iterations)) then
            if (size(h%newton_iterations) > 0) call note('series/newton/iterations')
        end if
        if (has_1(h%newton_residual)) call note('series/newton/residual')
        if (has_1(h%dt)) call note('series/dt')
        if (has_1(h%load_time)) call note('series/load_time')
        if (has_1(h%contact_energy)) call note('series/contact/energy')
        if (has_2(h%contact_force)) call note('series/contact/force')
        if (has_1(h%penetration)) call note('series/contact/penetration')
        if (has_2(h%friction_force)) call note('series/contact/friction')
        if (has_1(h%slip_speed)) call note('series/contact/slip_speed')
        if (has_3(h%tie_force)) call note('series/ties/force')
        if (has_3(h%tie_moment)) call note('series/ties/moment')
    contains
        subroutine note(path)
            character(len=*), intent(in) :: path
            layout%recorded = layout%recorded // path // ','
        end subroutine note
    end function layout_of

    !> A layout as flat arrays, for a broadcast (`unpack_layout` inverts).
    subroutine pack_layout(layout, header, values)
        type(rod_layout_t), intent(in) :: layout
        integer, allocatable, intent(out) :: header(:)
        real(rk), allocatable, intent(out) :: values(:)
        integer :: i
        header = [layout%n_nodes, layout%n_stress_points, layout%n_branches, layout%n_state, &
            layout%n_ledger, len(layout%name), len(layout%formulation), size(layout%mesh), &
            size(layout%stress_mesh), (ichar(layout%name(i:i)), i = 1, len(layout%name)), &
            (ichar(layout%formulation(i:i)), i = 1, len(layout%formulation)), &
            len(layout%recorded), (ichar(layout%recorded(i:i)), i = 1, len(layout%recorded)), &
            layout%checkpoint_rod]
        values = [layout%mesh, layout%stress_mesh]
    end subroutine pack_layout

    subroutine unpack_layout(header, values, layout)
        integer, intent(in) :: header(:)
        real(rk), intent(in) :: values(:)
        type(rod_layout_t), intent(out) :: layout
        integer :: i, at
        layout%n_nodes = header(1)
        layout%n_stress_points = header(2)
        layout%n_branches = header(3)
        layout%n_state = header(4)
        layout%n_ledger = header(5)
        allocate(character(len=header(6)) :: layout%name)
        allocate(character(len=header(7)) :: layout%formulation)
        at = 9
        do i = 1, header(6)
            layout%name(i:i) = achar(header(at + i))
        end do
        at = at + header(6)
        do i = 1, header(7)
            layout%formulation(i:i) = achar(header(at + i))
        end do
        at = at + header(7) + 1
        allocate(character(len=header(at)) :: layout%recorded)
        do i = 1, len(layout%recorded)
            layout%recorded(i:i) = achar(header(at + i))
        end do
        layout%checkpoint_rod = header(size(header))
        layout%mesh = values(1:header(8))
        layout%stress_mesh = values(header(8) + 1:header(8) + header(9))
    end subroutine unpack_layout

    !> Names in the comma-separated `selection` that are not selectable fields ('' if none;
    !> 'all' selects every field).
    function unknown_fields(selection) result(unknown)
        character(len=*), intent(in) :: selection
        character(len=:), allocatable :: unknown, item
        integer :: start, comma
        unknown = ''
        if (trim(adjustl(selection)) == 'all') return
        start = 1
        do
            comma = index(selection(start:), ',')
            if (comma == 0) then
                item = trim(adjustl(selection(start:)))
            else
                item = trim(adjustl(selection(start:start + comma - 2)))
            end if
            if (.not. field_selected(selectable_fields, item) .or. len(item) == 0) then
                if (len(unknown) > 0) unknown = unknown // ', '
                unknown = unknown // "'" // item // "'"
            end if
            if (comma == 0) exit
            start = start + comma
        end do
    end function unknown_fields

    !> True if `name` is one of the comma-separated names of `selection` (or selection is 'all').
    pure logical function field_selected(selection, name)
        character(len=*), intent(in) :: selection, name
        character(len=:), allocatable :: list
        integer :: k
        list = ',' // trim(adjustl(selection)) // ','
        if (list == ',all,') then
            field_selected = .true.
            return
        end if
        ! Spaces after commas are allowed.
        do
            k = index(list, ', ')
            if (k == 0) exit
            list = list(1:k) // list(k + 2:)
        end do
        field_selected = index(list, ',' // trim(name) // ',') > 0
    end function field_selected

    !> The growing datasets of a rod: the selected nodal and stress fields, then the series.
    function rod_fields(layout, selection) result(fields)
        type(rod_layout_t), intent(in) :: layout
        character(len=*), intent(in) :: selection
        type(field_t), allocatable :: fields(:)
        integer :: nn, ns, k
        nn = layout%n_nodes
        ns = layout%n_stress_points
        allocate(fields(0))
        if (index(layout%recorded, ',series/load_time,') > 0) then
            ! An arc-length continuation's records are its path steps.
            call add('time', [integer ::], '1', 'path step of each stored record (an ' // &
                'arc-length continuation: the load time is series/load_time), [step]')
        else
            call add('time', [integer ::], 's', 'time of each stored record, [step]')
        end if
        if (field_selected(selection, 'position')) call add('position', [3, nn], 'm', &
            'centreline position phi of the nodes in the spatial frame, [step, node, component]')
        if (field_selected(selection, 'directors')) call add('directors', [3, 3, nn], '1', &
            'directors of the nodes: [step, node, i, :] holds the spatial components of ' // &
            'd_(i+1) (h5py index i = 0, 1, 2 for d1, d2, d3)')
        if (field_selected(selection, 'velocity')) call add('velocity', [3, nn], 'm/s', &
            'centreline velocity of the nodes in the spatial frame, [step, node, component]')
        if (field_selected(selection, 'director_velocity')) call add('director_velocity', &
            [3, 3, nn], '1/s', 'time derivative of the directors: [step, node, i, :] holds ' // &
            'the spatial components of d(d_(i+1))/dt')
        if (ns > 0 .and. field_selected(selection, 'stress')) call add('stress', [6, ns], &
            stress_unit, 'total stress resultants (elastic branch plus all Maxwell branches) ' // &
            'at the stress points in material (director) components, [step, point, k] with k ' // &
            'over the attribute components: forces N and moments M; stress minus the sum of ' // &
            'branch_stress over the branches is the elastic-branch stress', stress_components)
        if (ns > 0 .and. field_selected(selection, 'strain')) call add('strain', [6, ns], &
            '1 (Gamma); 1/m (K)', 'strains computed from the displacements at the stress ' // &
            'points (straight reference: Gamma0 = (0, 0, 1), K0 = 0); strain consistency: ' // &
            'C sigma_elastic = strain - strain0 (methods/ph_director_3d.md §2.2, §5.3 item 3), ' // &
            '[step, point, k] with k over the attribute components', &
            'Gamma1 Gamma2 Gamma3 K1 K2 K3')
        if (ns > 0 .and. layout%n_branches > 0 .and. field_selected(selection, 'branch_stress')) &
            call add('branch_stress', [6, ns, layout%n_branches], stress_unit, &
            'stress resultants of the generalized-Maxwell branches at the stress points in ' // &
            'material (director) components, [step, branch, point, k] with k over the ' // &
            'attribute components (methods/ph_director_3d.md §3.1); stress minus their sum ' // &
            'over the branches is the elastic-branch stress', stress_components)
        do k = 1, size(energy_names)
            call add('series/energy/' // trim(energy_names(k)), [integer ::], 'J', &
                energy_description(energy_names(k)))
        end do
        do k = 1, size(momentum_names)
            call add('series/momentum/' // trim(momentum_names(k)), [3], &
                momentum_unit(momentum_names(k)), momentum_description(momentum_names(k)))
        end do
        call add('series/center_of_mass', [3], 'm', &
            'centre of mass of the centreline (1/L) int phi ds, [step, component]')
        call add('series/constraint_residual', [integer ::], '1', &
            'largest nodal orthonormality residual max_k |g(d_k)| (d_i . d_j - delta_ij) at ' // &
            'the record, [step]')
        call add('series/newton/iterations', [integer ::], '1', &
            'Newton iterations of the step that ended at this record, [step]', integer_values=.true.)
        call add('series/newton/residual', [integer ::], 'as newton_atol', &
            'final Newton residual norm of the step that ended at this record, in the row ' // &
            'scaling of the formulation''s method document (DESIGN.md §3), [step]')
        call add('series/dt', [integer ::], 's', 'time step that ended at this record ' // &
            '(after cut-backs, the smallest substep), [step]')
        call add('series/load_time', [integer ::], 's', 'arc-length continuation (&time ' // &
            'continuation): the load time of the path''s point at this record (the loads'' ' // &
            'time functions at it; /time holds the step number), [step]')
        if (field_selected(selection, 'contact')) then
            call add('series/contact/energy', [integer ::], 'J', 'the rod''s share of the ' // &
                'contact energy at the record: half the energy of each of its contact pairs ' // &
                '(rod-rod and self contact), [step]')
            call add('series/contact/force', [3], 'N', 'total contact force on the rod at ' // &
                'the record, spatial components, [step, component]')
            call add('series/contact/penetration', [integer ::], 'm', 'deepest penetration ' // &
                'r_c - d over the rod''s contact point pairs at the record (r_c the sum of ' // &
                'the contact radii, d the distance of the centrelines); 0 without contact, [step]')
            call add('series/contact/friction', [3], 'N', 'friction force on the rod in the ' // &
                'step that ended at the record (rod-rod and obstacles, &contact and ' // &
                '&obstacle mu), spatial components; 0 without friction, [step, component]')
            call add('series/contact/slip_speed', [integer ::], 'm/s', 'largest slip speed ' // &
                '|u| / h of the rod''s contact points in friction in that step, [step]')
        end if
        if (field_selected(selection, 'ties')) then
            call add('series/ties/force', [3, 2], 'N', &
                'force of the joints and end plates on the rod''s ends at the record, spatial ' // &
                'components, [step, end, component] with end 0 = start, 1 = end; zero at an ' // &
                'end no joint or plate ties')
            call add('series/ties/moment', [3, 2], 'N m', &
                'moment of the joints and end plates on the rod''s ends at the record (about ' // &
                'the end''s node), spatial components, [step, end, component] as ' // &
                'series/ties/force')
        end if
    contains
        subroutine add(path, dims, unit, description, components, integer_values)
            character(len=*), intent(in) :: path, unit, description
            integer, intent(in) :: dims(:)
            character(len=*), intent(in), optional :: components
            logical, intent(in), optional :: integer_values
            type(field_t) :: field
            if (index(layout%recorded, ',' // path // ',') == 0) return
            field%path = path
            field%dims = dims
            field%unit = unit
            field%description = description
            if (present(components)) field%components = components
            if (present(integer_values)) field%integer_values = integer_values
            fields = [fields, field]
        end subroutine add
    end function rod_fields

    !> Records first..last of field `path` of a history, flattened (Fortran order).
    function record_block(h, path, first, last) result(values)
        type(rod_history_t), intent(in) :: h
        character(len=*), intent(in) :: path
        integer, intent(in) :: first, last
        real(rk), allocatable :: values(:)
        real(rk), allocatable :: series(:)
        integer :: n
        n = last - first + 1
        select case (path)
        case ('time')
            values = h%time(first:last)
        case ('position')
            values = reshape(h%position(:, :, first:last), [3 * h%n_nodes * n])
        case ('directors')
            values = reshape(h%directors(:, :, :, first:last), [9 * h%n_nodes * n])
        case ('velocity')
            values = reshape(h%velocity(:, :, first:last), [3 * h%n_nodes * n])
        case ('director_velocity')
            values = reshape(h%director_velocity(:, :, :, first:last), [9 * h%n_nodes * n])
        case ('stress')
            values = reshape(h%stress(:, :, first:last), [6 * h%n_stress_points * n])
        case ('strain')
            values = reshape(h%strains(:, :, first:last), [6 * h%n_stress_points * n])
        case ('branch_stress')
            values = reshape(h%branch_stress(:, :, :, first:last), &
                [6 * h%n_stress_points * h%n_branches * n])
        case ('series/momentum/linear')
            values = reshape(h%linear_momentum(:, first:last), [3 * n])
        case ('series/momentum/angular')
            values = reshape(h%angular_momentum(:, first:last), [3 * n])
        case ('series/center_of_mass')
            values = reshape(h%center_of_mass(:, first:last), [3 * n])
        case ('series/constraint_residual')
            values = h%constraint_residual(first:last)
        case ('series/newton/residual')
            values = h%newton_residual(first:last)
        case ('series/dt')
            values = h%dt(first:last)
        case ('series/load_time')
            values = h%load_time(first:last)
        case ('series/contact/energy')
            values = h%contact_energy(first:last)
        case ('series/contact/force')
            values = reshape(h%contact_force(:, first:last), [3 * n])
        case ('series/contact/penetration')
            values = h%penetration(first:last)
        case ('series/contact/friction')
            values = reshape(h%friction_force(:, first:last), [3 * n])
        case ('series/contact/slip_speed')
            values = h%slip_speed(first:last)
        case ('series/ties/force')
            values = reshape(h%tie_force(:, :, first:last), [6 * n])
        case ('series/ties/moment')
            values = reshape(h%tie_moment(:, :, first:last), [6 * n])
        case default
            call energy_of(h, path(len('series/energy/') + 1:), series)
            values = series(first:last)
        end select
    end function record_block

    !> Rank 0, before the run: create the result file with its metadata, the input, every
    !> rod's group, meshes and empty growing datasets, and the checkpoint datasets. With
    !> `restart` (the file exists, copied from restart_from), keep the rods' records up to the
    !> checkpoint instead, replace the input, and check that the file fits the layouts.
    subroutine prepare_result_file(path, meta, layouts, selection, err, restart)
        character(len=*), intent(in) :: path, selection
        type(result_meta_t), intent(in) :: meta
        type(rod_layout_t), intent(in) :: layouts(:)
        type(error_t), allocatable, intent(out) :: err
        logical, intent(in), optional :: restart
        type(hdf5_file_t) :: file
        type(error_t), allocatable :: close_err
        logical :: restarting
        integer :: i

        restarting = .false.
        if (present(restart)) restarting = restart
        if (restarting) then
            call file%open(path, err)
            if (allocated(err)) return
            call restart_in_place(file, meta, layouts, selection, err)
        else
            call file%create(path, err)
            if (allocated(err)) return
            call write_root(file, meta, err)
            call write_input(file, meta, err)
            do i = 1, size(layouts)
                call create_rod(file, layouts(i), selection, system_of(meta), &
                    meta%n_ranks == 1, err)
            end do
        end if
        call file%close(close_err)
        if (.not. allocated(err) .and. allocated(close_err)) call move_alloc(close_err, err)
    end subroutine prepare_result_file

    !> The result file of a sweep (DESIGN.md §7): the root attributes and /input of the base
    !> scene; the caller adds /members/<id>/ and /summary.
    subroutine prepare_sweep_file(path, meta, file, err)
        character(len=*), intent(in) :: path
        type(result_meta_t), intent(in) :: meta
        type(hdf5_file_t), intent(inout) :: file
        type(error_t), allocatable, intent(out) :: err
        call file%create(path, err)
        if (allocated(err)) return
        call write_root(file, meta, err)
        if (allocated(err)) return
        call write_input(file, meta, err)
    end subroutine prepare_sweep_file

    !> /rods/<name>/ with its meshes and empty growing datasets; /checkpoint/<name>/.
    !> `checksums`: the growing datasets get HDF5's Fletcher-32 checksum (a file one rank
    !> writes; parallel HDF5 1.10 cannot write filtered datasets collectively).
    subroutine create_rod(file, layout, selection, system, checksums, err)
        type(hdf5_file_t), intent(inout) :: file
        type(rod_layout_t), intent(in) :: layout
        character(len=*), intent(in) :: selection, system
        logical, intent(in) :: checksums
        type(error_t), allocatable, intent(inout) :: err
        type(field_t), allocatable :: fields(:)
        character(len=:), allocatable :: group, checkpoint
        integer :: k
        if (allocated(err)) return
        group = '/rods/' // layout%name
        call file%create_group(group, err)
        if (allocated(err)) return
        call put_attribute(file, group, 'formulation', layout%formulation, err)
        if (allocated(err)) return
        if (size(layout%mesh) > 0) call file%write_dataset(group // '/mesh', layout%mesh, &
            unit_in_system('m', system), 'reference arc length s of the nodes, [node]', err)
        if (allocated(err)) return
        if (size(layout%stress_mesh) > 0) call file%write_dataset(group // '/stress_mesh', &
            layout%stress_mesh, unit_in_system('m', system), 'reference arc length of the stress points (the ' // &
            'element stress coefficients, element by element), [point]', err)
        if (allocated(err)) return
        fields = rod_fields(layout, selection)
        do k = 1, size(fields)
            call file%create_series(group // '/' // trim(fields(k)%path), fields(k)%dims, &
                fields(k)%integer_values, unit_text(trim(fields(k)%unit), system), &
                fields(k)%description, err, checksum=checksums)
            if (allocated(err)) return
            if (len_trim(fields(k)%components) > 0) call put_attribute(file, group // '/' // &
                trim(fields(k)%path), 'components', trim(fields(k)%components), err)
            if (allocated(err)) return
        end do
        if (layout%n_state == 0) return
        ! The checkpoint (DESIGN.md §7): written with data now, so that its storage exists and
        ! each rank can rewrite its rods' part independently at every flush.
        checkpoint = '/checkpoint/' // layout%name
        call file%write_dataset(checkpoint // '/state', [(0.0_rk, k = 1, layout%n_state)], &
            'mixed', 'state vector X of the formulation at the checkpoint step', err)
        if (allocated(err)) return
        if (layout%n_ledger > 0) then
            call file%write_dataset(checkpoint // '/ledger', [(0.0_rk, k = 1, layout%n_ledger)], &
                'mixed', 'the record ledger''s sums since the last record, ' // &
                str(ledger_entries) // ' entries per rod of the system in rod order (attribute ' // &
                'entries)', err)
            if (allocated(err)) return
            call put_attribute(file, checkpoint // '/ledger', 'entries', ledger_entry_names(), err)
            if (allocated(err)) return
        end if
        call file%write_dataset(checkpoint // '/step', [-1], '1', &
            'time step the checkpoint holds the state after (-1: none yet)', err)
        if (allocated(err)) return
        call file%write_dataset(checkpoint // '/records', [0], '1', &
            'records of the rod in the file at the checkpoint', err)
        if (allocated(err)) return
        call file%write_dataset(checkpoint // '/time', [0.0_rk], unit_in_system('s', system), &
            'time of the checkpoint', err)
        if (allocated(err)) return
        call file%write_dataset(checkpoint // '/checksum', checkpoint_checksum([(0.0_rk, k = 1, &
            layout%n_state)], [(0.0_rk, k = 1, layout%n_ledger)], -1, 0, 0.0_rk), '1', &
            'Fletcher checksum of state, ledger, step, records and time (reals as their ' // &
            'IEEE bytes, 32-bit words, sums modulo 2^32 - 1; docs/user/output.md), verified ' // &
            'by a restart', err)
    end subroutine create_rod

    !> A restart in the result file itself: check the rods against the layouts, cut each rod's
    !> datasets back to its checkpoint, drop /series (rebuilt at the end), replace the input and
    !> the run's root attributes.
    subroutine restart_in_place(file, meta, layouts, selection, err)
        type(hdf5_file_t), intent(inout) :: file
        type(result_meta_t), intent(in) :: meta
        type(rod_layout_t), intent(in) :: layouts(:)
        character(len=*), intent(in) :: selection
        type(error_t), allocatable, intent(inout) :: err
        type(field_t), allocatable :: fields(:)
        integer, allocatable :: dims(:), records(:)
        character(len=:), allocatable :: group
        integer :: i, k
        do i = 1, size(layouts)
            group = '/rods/' // layouts(i)%name
            if (layouts(i)%checkpoint_rod > 0) then
                ! Coupled to the system's first rod: as many records as that rod.
                call file%read('/checkpoint/' // layouts(layouts(i)%checkpoint_rod)%name // &
                    '/records', records, err)
                if (allocated(err)) return
                call cut_fields(records(1))
                if (allocated(err)) return
                cycle
            end if
            if (.not. file%exists('/checkpoint/' // layouts(i)%name // '/state')) then
                call set_error(err, 'the restart file "' // file%path // '" has no checkpoint ' // &
                    'of rod "' // layouts(i)%name // '"', 'prepare_result_file', __FILE__, __LINE__)
                return
            end if
            call file%dataset_dims('/checkpoint/' // layouts(i)%name // '/state', dims, err)
            if (allocated(err)) return
            if (dims(1) /= layouts(i)%n_state) then
                call set_error(err, 'the restart file "' // file%path // '" holds rod "' // &
                    layouts(i)%name // '" with ' // str(dims(1)) // ' state values, the scene ' // &
                    'gives it ' // str(layouts(i)%n_state) // ' (a different discretization?)', &
                    'prepare_result_file', __FILE__, __LINE__)
                return
            end if
            call file%read('/checkpoint/' // layouts(i)%name // '/records', records, err)
            if (allocated(err)) return
            call cut_fields(records(1))
            if (allocated(err)) return
        end do
        if (file%exists('/series')) call file%delete('/series', err)
        if (allocated(err)) return
        do k = 1, 3
            group = '/input/' // trim(input_names(k))
            if (file%exists(group)) call file%delete(group, err)
            if (allocated(err)) return
        end do
        call write_input(file, meta, err)
        call put_attribute(file, '/', 'command_line', text_of(meta%command_line), err)
        call put_attribute_int(file, '/', 'n_ranks', meta%n_ranks, err)
        call put_attribute(file, '/', 'restarted', iso_8601_now(), err)
    contains
        !> Cut every growing dataset of rod i to `n` records.
        subroutine cut_fields(n)
            integer, intent(in) :: n
            fields = rod_fields(layouts(i), selection)
            do k = 1, size(fields)
                if (.not. file%exists(group // '/' // trim(fields(k)%path))) then
                    call set_error(err, 'the restart file "' // file%path // '" has no ' // &
                        group // '/' // trim(fields(k)%path) // ' (&output fields differ?)', &
                        'prepare_result_file', __FILE__, __LINE__)
                    return
                end if
                call file%set_records(group // '/' // trim(fields(k)%path), n, err)
                if (allocated(err)) return
                if (meta%n_ranks > 1) call drop_checksum(group // '/' // trim(fields(k)%path), n)
                if (allocated(err)) return
            end do
        end subroutine cut_fields

        !> A file written on one rank continued on several: its checksummed dataset `path`
        !> is copied into one without the checksum, which parallel HDF5 1.10 cannot write.
        subroutine drop_checksum(path, n)
            character(len=*), intent(in) :: path
            integer, intent(in) :: n
            real(rk), allocatable :: values(:)
            integer, allocatable :: integers(:)
            if (.not. file%has_filters(path, err)) return
            if (allocated(err)) return
            if (fields(k)%integer_values) then
                call file%read(path, integers, err)
            else
                call file%read(path, values, err)
            end if
            if (allocated(err)) return
            call file%delete(path, err)
            if (allocated(err)) return
            call file%create_series(path, fields(k)%dims, fields(k)%integer_values, &
                unit_text(trim(fields(k)%unit), system_of(meta)), fields(k)%description, err)
            if (allocated(err)) return
            if (len_trim(fields(k)%components) > 0) call put_attribute(file, path, &
                'components', trim(fields(k)%components), err)
            if (allocated(err)) return
            call file%set_records(path, n, err)
            if (allocated(err) .or. n == 0) return
            if (fields(k)%integer_values) then
                call file%write_records(path, 1, integers, err)
            else
                call file%write_records(path, 1, values, err)
            end if
        end subroutine drop_checksum
    end subroutine restart_in_place

    !> Read the checkpoint of rod `name` from `path` (rank that owns the rod; serial driver).
    subroutine read_checkpoint(path, name, state, ledger, step, records, time, err)
        character(len=*), intent(in) :: path, name
        !> The state and the record ledger's sums (rs_system_ledger).
        real(rk), allocatable, intent(out) :: state(:), ledger(:)
        integer, intent(out) :: step, records
        real(rk), intent(out) :: time
        type(error_t), allocatable, intent(out) :: err
        type(hdf5_file_t) :: file
        type(error_t), allocatable :: close_err
        character(len=:), allocatable :: group
        integer, allocatable :: values(:)
        real(rk), allocatable :: times(:)
        integer :: sums(2)
        logical :: mismatch
        step = -1
        records = 0
        time = 0.0_rk
        call file%open(path, err, writable=.false.)
        if (allocated(err)) return
        group = '/checkpoint/' // name
        body: block
            if (.not. file%exists(group // '/state')) then
                call set_error(err, 'the restart file "' // path // '" has no checkpoint of ' // &
                    'rod "' // name // '"', 'read_checkpoint', __FILE__, __LINE__)
                exit body
            end if
            call file%read(group // '/state', state, err)
            if (allocated(err)) exit body
            if (file%exists(group // '/internal')) then
                ! Schema 1 kept each formulation's own book-keeping in its own layout.
                call set_error(err, 'the checkpoint of rod "' // name // '" in "' // path // &
                    '" was written by an older rodsolve (schema 1: /internal, the ' // &
                    'formulation''s own book-keeping); this version reads schema ' // &
                    str(result_schema_version) // ' (/ledger): run the scene again from the ' // &
                    'start', 'read_checkpoint', __FILE__, __LINE__)
                exit body
            end if
            allocate(ledger(0))
            if (file%exists(group // '/ledger')) call file%read(group // '/ledger', ledger, err)
            if (allocated(err)) exit body
            call file%read(group // '/step', values, err)
            if (allocated(err)) exit body
            step = values(1)
            call file%read(group // '/records', values, err)
            if (allocated(err)) exit body
            records = values(1)
            call file%read(group // '/time', times, err)
            if (allocated(err)) exit body
            time = times(1)
            if (step < 0) then
                call set_error(err, 'the restart file "' // path // '" holds no ' // &
                    'checkpoint yet (the run stopped before its first flush)', 'read_checkpoint', &
                    __FILE__, __LINE__)
                exit body
            end if
            ! Damage on disk (or a torn write) must not be continued silently (issue 21 item 21).
            if (.not. file%exists(group // '/checksum')) then
                call set_error(err, 'the checkpoint of rod "' // name // '" in "' // path // &
                    '" has no checksum (written by an older rodsolve): it cannot be verified', &
                    'read_checkpoint', __FILE__, __LINE__)
                exit body
            end if
            call file%read(group // '/checksum', values, err)
            if (allocated(err)) exit body
            sums = checkpoint_checksum(state, ledger, step, records, time)
            if (size(values) /= 2) then
                mismatch = .true.
            else
                mismatch = any(values /= sums)
            end if
            if (mismatch) call set_error(err, 'the checkpoint of rod "' // name // '" in "' // &
                path // '" is corrupted: its checksum does not match its values (the file ' // &
                'was damaged on disk or in a copy); restart from an intact copy, or run ' // &
                'the scene from the start', 'read_checkpoint', __FILE__, __LINE__)
        end block body
        call file%close(close_err)
        if (.not. allocated(err) .and. allocated(close_err)) call move_alloc(close_err, err)
    end subroutine read_checkpoint

    !> Rank 0, after the run: /series/ (the time grid and the energies and momenta summed over
    !> the rods, over the records every rod has) and the run's status; with `series` false
    !> only the status (after a write failed: a full disk takes no new datasets).
    subroutine finish_result_file(path, layouts, status, err, units, series)
        character(len=*), intent(in) :: path, status
        type(rod_layout_t), intent(in) :: layouts(:)
        type(error_t), allocatable, intent(out) :: err
        character(len=*), intent(in), optional :: units
        logical, intent(in), optional :: series
        type(hdf5_file_t) :: file
        type(error_t), allocatable :: close_err
        real(rk), allocatable :: time(:), values(:), total(:)
        character(len=:), allocatable :: name, system
        integer :: i, k, n
        logical :: everywhere
        system = 'si'
        if (present(units)) system = units
        call file%open(path, err)
        if (allocated(err)) return
        body: block
            if (present(series)) then
                if (.not. series) then
                    call put_attribute(file, '/', 'status', status, err)
                    exit body
                end if
            end if
            n = huge(1)
            do i = 1, size(layouts)
                call file%read('/rods/' // layouts(i)%name // '/time', values, err)
                if (allocated(err)) exit body
                if (size(values) < n) time = values
                n = min(n, size(values))
            end do
            if (file%exists('/series')) call file%delete('/series', err)
            if (allocated(err)) exit body
            if (index(layouts(1)%recorded, ',series/load_time,') > 0) then
                ! An arc-length continuation: the records are its path steps.
                call file%write_dataset('/series/time', time, '1', 'path step of each ' // &
                    'stored record, shared by all rods (the load times are the rods'' ' // &
                    'series/load_time), [step]', err, series=.true.)
            else
                call file%write_dataset('/series/time', time, unit_in_system('s', system), &
                    'time of each stored record, shared by all rods, [step]', err, series=.true.)
            end if
            if (allocated(err)) exit body
            do k = 1, size(energy_names) + size(momentum_names)
                if (k <= size(energy_names)) then
                    name = 'energy/' // trim(energy_names(k))
                    allocate(total(n), source=0.0_rk)
                else
                    name = 'momentum/' // trim(momentum_names(k - size(energy_names)))
                    allocate(total(3 * n), source=0.0_rk)
                end if
                everywhere = .true.
                do i = 1, size(layouts)
                    everywhere = file%exists('/rods/' // layouts(i)%name // '/series/' // name)
                    if (.not. everywhere) exit
                    call file%read('/rods/' // layouts(i)%name // '/series/' // name, values, err)
                    if (allocated(err)) exit body
                    total = total + values(1:size(total))
                end do
                if (.not. everywhere) then
                    ! A sum only of what every rod has.
                    deallocate(total)
                    cycle
                end if
                if (k <= size(energy_names)) then
                    call file%write_dataset('/series/' // name, total, unit_in_system('J', system), &
                        'sum over all rods: ' // &
                        energy_description(energy_names(k)), err, series=.true.)
                else
                    call file%write_dataset('/series/' // name, reshape(total, [3, n]), &
                        unit_in_system(momentum_unit(name(10:)), system), 'sum over all rods: ' // &
                        momentum_description(name(10:)), err, series=.true.)
                end if
                deallocate(total)
                if (allocated(err)) exit body
            end do
            call put_attribute(file, '/', 'status', status, err)
        end block body
        call file%close(close_err)
        if (.not. allocated(err) .and. allocated(close_err)) call move_alloc(close_err, err)
    end subroutine finish_result_file

    ! ---- the writer of a run ------------------------------------------------------------------

    !> Open the prepared result file with the layouts of all rods and the records each has in
    !> the file already.
    subroutine writer_open(this, path, layouts, selection, n_records, parallel, err)
        class(result_writer_t), intent(inout) :: this
        character(len=*), intent(in) :: path, selection
        type(rod_layout_t), intent(in) :: layouts(:)
        integer, intent(in) :: n_records(:)
        !> Open on every rank of MPI_COMM_WORLD with MPI-IO.
        logical, intent(in) :: parallel
        type(error_t), allocatable, intent(out) :: err
        integer :: i
        this%layouts = layouts
        allocate(this%fields(size(layouts)))
        do i = 1, size(layouts)
            this%fields(i)%list = rod_fields(layouts(i), selection)
        end do
        this%n_records = n_records
        this%committed = n_records
        call this%file%open(path, err, parallel=parallel)
    end subroutine writer_open

    !> Collective: every rod's growing datasets get `totals(rod)` records (the same on every
    !> rank); the new records of a rod are the last ones of its history.
    subroutine writer_extend(this, totals, err)
        class(result_writer_t), intent(inout) :: this
        integer, intent(in) :: totals(:)
        type(error_t), allocatable, intent(out) :: err
        call this%set_all_records(totals, err)
        this%n_records = totals
    end subroutine writer_extend

    !> One rank (of a parallel file: rank 0): reserve the disk the chunks of `totals(rod)`
    !> records need beyond the chunks of the records in the file, with room for the metadata
    !> that grows with them (chunk index nodes: 64 KiB and 4 KiB a dataset, several times what
    !> a flush of the examples adds). A full disk or a file-size limit is found here, before
    !> anything is extended, so the file stays whole and can still be marked 'failed' (issue 21
    !> item 3).
    subroutine writer_reserve(this, totals, err)
        class(result_writer_t), intent(inout) :: this
        integer, intent(in) :: totals(:)
        type(error_t), allocatable, intent(out) :: err
        integer(int64) :: bytes, record_bytes
        integer :: i, k, chunk
        bytes = 64 * 1024
        do i = 1, size(this%layouts)
            do k = 1, size(this%fields(i)%list)
                associate (field => this%fields(i)%list(k))
                    record_bytes = merge(4_int64, 8_int64, field%integer_values) * &
                        product(int(field%dims, int64))
                    chunk = series_chunk_records(int(record_bytes, hsize_t))
                    bytes = bytes + 4 * 1024 + record_bytes * chunk * &
                        (chunks(totals(i), chunk) - chunks(this%n_records(i), chunk))
                end associate
            end do
        end do
        call this%file%reserve(bytes, err)
    contains
        pure integer function chunks(n, per_chunk)
            integer, intent(in) :: n, per_chunk
            chunks = (n + per_chunk - 1) / per_chunk
        end function chunks
    end subroutine writer_reserve

    !> Collective: every growing dataset of rod i gets `totals(i)` records; every call is made
    !> even after a failure (the first error is returned).
    subroutine writer_set_all_records(this, totals, err)
        class(result_writer_t), intent(inout) :: this
        integer, intent(in) :: totals(:)
        type(error_t), allocatable, intent(out) :: err
        type(error_t), allocatable :: one_err
        integer :: i, k
        do i = 1, size(this%layouts)
            do k = 1, size(this%fields(i)%list)
                call this%file%set_records('/rods/' // this%layouts(i)%name // '/' // &
                    trim(this%fields(i)%list(k)%path), totals(i), one_err)
                if (allocated(one_err) .and. .not. allocated(err)) call move_alloc(one_err, err)
                if (allocated(one_err)) deallocate(one_err)
            end do
        end do
    end subroutine writer_set_all_records

    !> After every rank's flush succeeded (the caller agreed on it): the records in the file
    !> are on disk.
    subroutine writer_commit_records(this)
        class(result_writer_t), intent(inout) :: this
        this%committed = this%n_records
    end subroutine writer_commit_records

    !> Collective, after a write or flush failed on some rank: every rod's datasets are cut
    !> back to the committed records and the file is flushed, so that every record the file
    !> lists holds what was written (the cut chunks are dropped with their extent).
    subroutine writer_drop_unflushed(this, err)
        class(result_writer_t), intent(inout) :: this
        type(error_t), allocatable, intent(out) :: err
        type(error_t), allocatable :: flush_err
        call this%set_all_records(this%committed, err)
        this%n_records = this%committed
        call this%file%flush(flush_err)
        if (.not. allocated(err) .and. allocated(flush_err)) call move_alloc(flush_err, err)
    end subroutine writer_drop_unflushed

    !> Collective: write rod i's new records (the last ones of its history, after `extend`);
    !> the rod's owner passes its history, every other rank none. After a failure the owner
    !> takes part in the remaining writes with nothing (the first error is returned).
    subroutine writer_write_records(this, i, err, h)
        class(result_writer_t), intent(inout) :: this
        integer, intent(in) :: i
        type(error_t), allocatable, intent(out) :: err
        type(rod_history_t), intent(in), optional :: h
        type(error_t), allocatable :: one_err
        character(len=:), allocatable :: path
        integer :: k, first
        logical :: writes
        writes = present(h)
        if (writes) writes = h%n_stored > 0
        do k = 1, size(this%fields(i)%list)
            path = '/rods/' // this%layouts(i)%name // '/' // trim(this%fields(i)%list(k)%path)
            if (.not. writes .or. allocated(err)) then
                call this%file%write_no_records(path, one_err)
            else if (this%fields(i)%list(k)%integer_values) then
                first = this%n_records(i) - h%n_stored + 1
                call this%file%write_records(path, first, h%newton_iterations(1:h%n_stored), &
                    one_err)
            else
                first = this%n_records(i) - h%n_stored + 1
                call this%file%write_records(path, first, &
                    record_block(h, trim(this%fields(i)%list(k)%path), 1, h%n_stored), one_err)
            end if
            if (allocated(one_err) .and. .not. allocated(err)) call move_alloc(one_err, err)
            if (allocated(one_err)) deallocate(one_err)
        end do
    end subroutine writer_write_records

    !> Collective: rod i's checkpoint, its state and the record ledger's sums after
    !> `step`, at `time`, with their checksum; the rod's owner passes them, every other rank
    !> neither. After a failure the owner takes part in the remaining writes with nothing (the
    !> first error is returned).
    subroutine writer_write_checkpoint(this, i, step, time, err, state, ledger)
        class(result_writer_t), intent(inout) :: this
        integer, intent(in) :: i, step
        real(rk), intent(in) :: time
        type(error_t), allocatable, intent(out) :: err
        real(rk), intent(in), optional :: state(:), ledger(:)
        character(len=:), allocatable :: group
        ! A rod coupled to another has its state in that rod's checkpoint.
        if (this%layouts(i)%checkpoint_rod > 0) return
        group = '/checkpoint/' // this%layouts(i)%name
        if (present(state)) then
            call put_records(group // '/state', state)
            if (this%layouts(i)%n_ledger > 0) call put_records(group // '/ledger', ledger)
            call put_integers(group // '/step', [step])
            call put_integers(group // '/records', [this%n_records(i)])
            call put_records(group // '/time', [time])
            call put_integers(group // '/checksum', checkpoint_checksum(state, ledger, step, &
                this%n_records(i), time))
        else
            call put_nothing(group // '/state')
            if (this%layouts(i)%n_ledger > 0) call put_nothing(group // '/ledger')
            call put_nothing(group // '/step')
            call put_nothing(group // '/records')
            call put_nothing(group // '/time')
            call put_nothing(group // '/checksum')
        end if
    contains
        subroutine put_records(path, values)
            character(len=*), intent(in) :: path
            real(rk), intent(in) :: values(:)
            type(error_t), allocatable :: one_err
            if (allocated(err)) then
                call put_nothing(path)
                return
            end if
            call this%file%write_records(path, 1, values, one_err)
            if (allocated(one_err)) call move_alloc(one_err, err)
        end subroutine put_records

        subroutine put_integers(path, values)
            character(len=*), intent(in) :: path
            integer, intent(in) :: values(:)
            type(error_t), allocatable :: one_err
            if (allocated(err)) then
                call put_nothing(path)
                return
            end if
            call this%file%write_records(path, 1, values, one_err)
            if (allocated(one_err)) call move_alloc(one_err, err)
        end subroutine put_integers

        subroutine put_nothing(path)
            character(len=*), intent(in) :: path
            type(error_t), allocatable :: one_err
            call this%file%write_no_records(path, one_err)
            if (allocated(one_err) .and. .not. allocated(err)) call move_alloc(one_err, err)
        end subroutine put_nothing
    end subroutine writer_write_checkpoint

    subroutine writer_flush(this, err)
        class(result_writer_t), intent(inout) :: this
        type(error_t), allocatable, intent(out) :: err
        call this%file%flush(err)
    end subroutine writer_flush

    subroutine writer_close(this, err)
        class(result_writer_t), intent(inout) :: this
        type(error_t), allocatable, intent(out) :: err
        call this%file%close(err)
    end subroutine writer_close

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
            if (too_short_1(h%load_time, h%n_stored)) what = 'load_time'
            if (too_short_1(h%contact_energy, h%n_stored)) what = 'contact_energy'
            if (too_short_2(h%contact_force, h%n_stored)) what = 'contact_force'
            if (too_short_1(h%penetration, h%n_stored)) what = 'penetration'
            if (too_short_2(h%friction_force, h%n_stored)) what = 'friction_force'
            if (too_short_1(h%slip_speed, h%n_stored)) what = 'slip_speed'
            if (too_short_3(h%tie_force, h%n_stored)) what = 'tie_force'
            if (too_short_3(h%tie_moment, h%n_stored)) what = 'tie_moment'
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
        call put_attribute(file, '/', 'units', system_of(meta), err)
    end subroutine write_root

    !> The scene's system of units ('si' when not given).
    pure function system_of(meta) result(system)
        type(result_meta_t), intent(in) :: meta
        character(len=:), allocatable :: system
        system = 'si'
        if (allocated(meta%units)) then
            if (len_trim(meta%units) > 0) system = trim(meta%units)
        end if
    end function system_of

    !> A field's SI unit text in `system`; the stress unit names its components, which are
    !> not units.
    pure function unit_text(si_unit, system) result(text)
        character(len=*), intent(in) :: si_unit, system
        character(len=:), allocatable :: text
        if (si_unit == stress_unit) then
            text = unit_in_system('N', system) // ' (N1, N2, N3); ' // &
                unit_in_system('N m', system) // ' (M1, M2, M3)'
        else
            text = unit_in_system(si_unit, system)
        end if
    end function unit_text

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
    ! at its end.

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

    pure logical function has_4(values)
        real(rk), allocatable, intent(in) :: values(:, :, :, :)
        has_4 = .false.
        if (allocated(values)) has_4 = size(values) > 0
    end function has_4

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
