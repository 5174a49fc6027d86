#include "rs_macros.h"
!> Modal analysis of a scene (&modes; issue 27 item 1, docs/theory/modes.md), after its run:
!> for every system (one rod, or the rods that joints, plates or contact couple), the
!> equations of motion linearized about the reference state or the end state of a quasistatic
!> run with the loads of its load time (t_end, or a continuation's last point's:
!> system_state_t) (rs_system_linearization, from the step Jacobians of the system built for
!> dynamics with the midpoint rule, whatever the run's scheme: couplings and constraints
!> included), their lowest modes
!> (rs_solver_modal_solver, SLEPc on all ranks together), and on rank 0 the frequencies and
!> the mode shapes in /modes of the result file (docs/user/output.md) and the modes sidecar
!> FILE.modes.xdmf (docs/user/postprocessing.md). Linearized buckling (kind = 'buckling')
!> compares the tangent stiffnesses of the reference and of the loaded equilibrium
!> (rs_system_linearization's buckling_stiffness; build_system) and writes /buckling.
module rs_app_run_modes
    use rs_core_kinds, only: rk, pi
    use rs_core_error, only: error_t, set_error
    use rs_core_logger, only: log_info, log_warning
    use rs_core_strings, only: str, str_significant
    use rs_core_timer, only: wall_time
    use rs_model_scene, only: scene_t
    use rs_model_units, only: unit_in_system
    use rs_model_coupling, only: coupled_systems
    use rs_parallel_mpi_env, only: world_rank, world_size, any_rank_true, broadcast_text
    use rs_formulations_formulation, only: formulation_traits_t, modal_first_order, &
        max_node_coordinates
    use rs_system_rod_system, only: rod_system_t
    use rs_math_so3, only: exp_so3, tangent_so3, hat
    use rs_system_linearization, only: pencil_t, linearize_system, buckling_stiffness
    use rs_solver_modal_solver, only: modes_t, solve_modes, solve_buckling, lowest_elastic
    use rs_io_hdf5_file, only: hdf5_file_t
    use rs_io_xdmf_writer, only: xdmf_mode_rod_t, write_xdmf_modes_sidecar, &
        xdmf_modes_sidecar_path
    implicit none
    private

    public :: run_modes

    !> The state of one system (in coupled_systems' order) at the end of the run, whole on
    !> every rank, and its load time: what about = 'equilibrium' linearizes about, with the
    !> loads of that time (rod_runner_t%load_time: t_end after load steps, the path's last
    !> point's after a continuation, which may be anywhere).
    type, public :: system_state_t
        real(rk), allocatable :: x(:)
        real(rk) :: load_time = 0.0_rk
    end type system_state_t


contains

    !> The modes of every system of `scene` into the result file at `path` (which the run has
    !> completed); `states` are the systems' end states and their load times (about =
    !> 'equilibrium'). Collective on all ranks; `err` is set on every rank.
    subroutine run_modes(scene, path, states, err)
        type(scene_t), intent(in) :: scene
        character(len=*), intent(in) :: path
        type(system_state_t), intent(in) :: states(:)
        type(error_t), allocatable, intent(out) :: err
        type(scene_t) :: dynamic
        integer, allocatable :: system_of(:), first(:), members(:)
        type(rod_system_t), allocatable :: system
        type(pencil_t) :: pencil, reference
        type(modes_t) :: modes
        type(xdmf_mode_rod_t), allocatable :: sidecar(:), rods(:)
        real(rk), allocatable :: x(:)
        real(rk) :: started, t
        integer :: k
        character(len=:), allocatable :: name, message
        logical :: equilibrium, buckling
        ! The modes are the dynamic midpoint step's, whatever the run solved (statics,
        ! generalized-alpha): its objects carry the mass terms and the midpoint form.
        dynamic = scene
        dynamic%time%quasistatic = .false.
        dynamic%time%scheme = 'midpoint'
        equilibrium = trim(scene%modes%about) == 'equilibrium'
        buckling = trim(scene%modes%kind) == 'buckling'
        call coupled_systems(scene, system_of, first, members)
        allocate(sidecar(0))
        do k = 1, size(first) - 1
            started = wall_time()
            ! The loads of the state: those of t = 0, or of the end state's own load time
            ! (after a continuation not t_end: the path's last point may be anywhere).
            t = 0.0_rk
            if (equilibrium) t = states(k)%load_time
            ! Every rank builds the whole system (a modal analysis is one linearization and
            ! one eigen solve: the assembly is cheap next to the solve, which is distributed).
            call build_system(scene, dynamic, members(first(k):first(k + 1) - 1), buckling, &
                system, err)
            if (.not. allocated(err)) then
                allocate(x(system%n_state()))
                call system%initial_state(x)
                if (equilibrium) call equilibrium_state(system, states(k)%x, x, err)
            end if
            if (buckling) then
                ! The modes are drawn about the state the geometric stiffness is about.
                if (.not. allocated(err)) call buckling_stiffness(system, t, x, scene%time%dt, &
                    reference, pencil, err)
                if (.not. allocated(err)) call solve_buckling(reference, pencil, &
                    scene%modes%n_modes, modes, err)
            else
                if (.not. allocated(err)) call linearize_system(system, t, x, scene%time%dt, &
                    pencil, err)
                if (.not. allocated(err)) call solve_modes(pencil, scene%modes%n_modes, modes, err)
            end if
            name = system_name(scene, members(first(k):first(k + 1) - 1))
            if (allocated(err)) then
                err%message = trim(merge('buckling of', 'modes of   ', buckling)) // ' ' // &
                    name // ': ' // err%message
                return
            end if
            call log_modes(name, pencil, modes, wall_time() - started)
            if (world_rank() == 0) then
                call write_modes(scene, path, name, system, x, t, pencil, modes, rods, err)
                if (.not. allocated(err)) sidecar = [sidecar, rods]
            end if
            deallocate(system, x)
            if (any_rank_true(allocated(err))) exit
        end do
        message = ''
        if (world_rank() == 0 .and. .not. allocated(err) .and. scene%output%xdmf) then
            ! Without node access (ph_planar) there is nothing to show: no sidecar, and none
            ! left over from an earlier run of the scene.
            if (size(sidecar) > 0) then
                call write_xdmf_modes_sidecar(path, sidecar, err)
            else
                call remove_file(xdmf_modes_sidecar_path(path))
            end if
        end if
        if (world_rank() == 0 .and. allocated(err)) message = err%describe()
        if (.not. any_rank_true(len(message) > 0)) return
        call broadcast_text(message, 0)
        if (.not. allocated(err)) then
            RS_SET_ERROR(err, 'run_modes', message)
        end if
    end subroutine run_modes

    !> The system of the rods `rods`, allocated: built for dynamics with the midpoint rule
    !> (`dynamic`), whose step Jacobians give the modes and a second-order pencil's stiffness;
    !> for linearized buckling (`buckling`) first as the run had it (`scene`), so that a
    !> formulation whose static problem has the tangent stiffness as its Jacobian
    !> (formulation_traits_t%static_tangent: ph_director) gives it from the problem the run
    !> solved (rs_system_linearization's buckling_stiffness), and for dynamics otherwise.
    subroutine build_system(scene, dynamic, rods, buckling, system, err)
        type(scene_t), intent(in) :: scene, dynamic
        integer, intent(in) :: rods(:)
        logical, intent(in) :: buckling
        type(rod_system_t), allocatable, intent(out) :: system
        type(error_t), allocatable, intent(out) :: err
        type(formulation_traits_t) :: traits
        if (buckling) then
            allocate(system)
            call system%init(scene, rods, err)
            RS_RETURN_IF_ERROR(err)
            traits = system%traits()
            if (traits%static_tangent) return
            deallocate(system)
        end if
        allocate(system)
        call system%init(dynamic, rods, err)
    end subroutine build_system

    !> The run's end state `from` as the system's state x, at rest: the same layout (a
    !> static object's state has the dynamic one's), checked by its length, with the load
    !> path's rates removed (rod_system_t%rest_state).
    subroutine equilibrium_state(system, from, x, err)
        type(rod_system_t), intent(in) :: system
        real(rk), allocatable, intent(in) :: from(:)
        real(rk), intent(inout) :: x(:)
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: message
        if (.not. allocated(from)) then
            RS_SET_ERROR(err, 'run_modes', 'no end state of the run to linearize about')
            return
        end if
        if (size(from) /= size(x)) then
            message = 'the quasistatic run''s state of ' // system%formulation // ' has ' // &
                str(size(from)) // ' entries, its dynamic step ' // str(size(x)) // &
                ': about = ''equilibrium'' is not available for it yet'
            RS_SET_ERROR(err, 'run_modes', message)
            return
        end if
        x = from
        call system%rest_state(x)
    end subroutine equilibrium_state

    !> Delete the file `path` if it exists.
    subroutine remove_file(path)
        character(len=*), intent(in) :: path
        integer :: unit, status
        open(newunit=unit, file=path, status='old', iostat=status)
        if (status == 0) close(unit, status='delete')
    end subroutine remove_file

    !> The system's name: its rods' names joined by '+'.
    function system_name(scene, rods) result(name)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: rods(:)
        character(len=:), allocatable :: name
        integer :: i
        name = trim(scene%rods(rods(1))%name)
        do i = 2, size(rods)
            name = name // '+' // trim(scene%rods(rods(i))%name)
        end do
    end function system_name

    subroutine log_modes(name, pencil, modes, seconds)
        character(len=*), intent(in) :: name
        type(pencil_t), intent(in) :: pencil
        type(modes_t), intent(in) :: modes
        real(rk), intent(in) :: seconds
        character(len=:), allocatable :: line
        real(rk) :: lowest
        integer :: k, rigid
        if (allocated(modes%load_factor)) then
            line = ''
            do k = 1, modes%n
                line = line // ' ' // str_significant(modes%load_factor(k), 10)
            end do
            call log_info('rodsolve: buckling of ' // name // ': ' // str(modes%n) // &
                ' load factors of the run''s loads (' // str(pencil%n) // ' unknowns), ' // &
                modes%solver // ', ' // str_significant(seconds, 3) // ' s:' // line)
            return
        end if
        lowest = lowest_elastic(modes%omega(1:modes%n))
        rigid = count(abs(modes%omega(1:modes%n)) < 1.0e-3_rk * lowest)
        call log_info('rodsolve: modes of ' // name // ': ' // str(modes%n) // ' modes (' // &
            str(rigid) // ' rigid-body), ' // trim(merge('first ', 'second', pencil%form == &
            modal_first_order)) // '-order pencil of ' // str(pencil%n) // ' unknowns (' // &
            str(pencil%n_algebraic) // ' algebraic rows), ' // modes%solver // ', ' // &
            str_significant(seconds, 3) // ' s')
        if (pencil%unbalance > 1.0e-8_rk) call log_warning('rodsolve: modes of ' // name // &
            ': the state is not in equilibrium (relative unbalance ' // &
            str_significant(pencil%unbalance, 3) // '): the modes are those of its tangent ' // &
            'stiffness, without the loads'' prestress')
        line = ''
        do k = 1, modes%n
            line = line // ' ' // str_significant(modes%omega(k) / (2.0_rk * pi), 8)
        end do
        call log_info('rodsolve: modes of ' // name // ': frequencies (Hz):' // line)
    end subroutine log_modes

    !> /modes/<system>/: frequencies and, per rod, the reference positions of its nodes and
    !> the mode shapes as nodal displacements, each mode scaled to a largest nodal
    !> displacement of 1 over the system (rank 0); the load time t of the loads linearized
    !> with as an attribute.
    subroutine write_modes(scene, path, name, system, x, t, pencil, modes, rods, err)
        type(scene_t), intent(in) :: scene
        character(len=*), intent(in) :: path, name
        type(rod_system_t), intent(in) :: system
        real(rk), intent(in) :: x(:), t
        type(pencil_t), intent(in) :: pencil
        type(modes_t), intent(in) :: modes
        type(xdmf_mode_rod_t), allocatable, intent(out) :: rods(:)
        type(error_t), allocatable, intent(out) :: err
        type(hdf5_file_t) :: file
        type(error_t), allocatable :: close_err
        real(rk), allocatable :: position(:, :), displacement(:, :, :), rotation(:, :, :), &
            scale(:), shapes(:, :)
        real(rk) :: extent
        character(len=:), allocatable :: group, units, hz
        integer :: m, n, n_shown
        n_shown = 0
        units = trim(scene%run%units)
        hz = merge('Hz ', '1/s', units == 'si')
        if (units /= 'si') hz = unit_in_system('1/s', units)
        group = '/modes/' // name
        if (allocated(modes%load_factor)) group = '/buckling/' // name
        allocate(rods(size(system%members)))
        call file%open(path, err)
        if (allocated(err)) return
        body: block
            call file%create_group(group, err)
            if (allocated(err)) exit body
            n = modes%n
            if (allocated(modes%load_factor)) then
                ! Linearized buckling: load factors, no frequencies.
                call file%write_dataset(group // '/load_factor', modes%load_factor(1:n), '-', &
                    'critical load factor lambda of each buckling mode relative to the run''s ' // &
                    'loads (those of the end state''s load time, attribute load_time), ' // &
                    'smallest |lambda| first (negative: the reversed loads), [mode]', err)
                if (.not. allocated(err)) call file%write_dataset(group // '/residual', &
                    modes%residual(1:n), '-', 'backward error of each eigenpair (SLEPc, ' // &
                    '|r| / ((|A| + |mu| |B|) |x|) of the equilibrated pencil), [mode]', err)
                if (.not. allocated(err)) call file%write_attribute(group, 'solver', &
                    modes%solver, err)
                if (.not. allocated(err)) call file%write_attribute(group, 'unbalance', &
                    pencil%unbalance, err)
                if (.not. allocated(err)) call file%write_attribute(group, 'load_time', t, err)
                if (allocated(err)) exit body
            else
                call file%write_dataset(group // '/frequency', modes%omega(1:n) / (2.0_rk * pi), &
                    trim(hz), 'frequency f = omega / (2 pi) of each mode, lowest first (negative: ' // &
                    'omega^2 < 0, an unstable state), [mode]', err)
                if (allocated(err)) exit body
                call file%write_dataset(group // '/angular_frequency', modes%omega(1:n), &
                    unit_in_system('rad/s', units), 'angular frequency omega of each mode, ' // &
                    '[mode]', err)
                if (allocated(err)) exit body
                call file%write_dataset(group // '/decay_rate', modes%decay(1:n), &
                    unit_in_system('1/s', units), 'decay rate delta of each mode, s = -delta +- ' // &
                    'i omega (zero without damping), [mode]', err)
                if (allocated(err)) exit body
                call file%write_dataset(group // '/residual', modes%residual(1:n), '-', &
                    'backward error of each eigenpair (SLEPc, |r| / ((|A| + |mu| |B|) ' // &
                    '|x|) of the equilibrated pencil), [mode]', err)
                if (allocated(err)) exit body
                call file%write_attribute(group, 'about', trim(scene%modes%about), err)
                if (.not. allocated(err)) call file%write_attribute(group, 'solver', modes%solver, err)
                if (.not. allocated(err)) call file%write_attribute(group, 'pencil', &
                    trim(merge('first ', 'second', pencil%form == modal_first_order)) // '-order', err)
                if (.not. allocated(err)) call file%write_attribute(group, 'unbalance', &
                    pencil%unbalance, err)
                if (.not. allocated(err)) call file%write_attribute(group, 'load_time', t, err)
                if (allocated(err)) exit body
            end if
            shapes = node_phase(system, modes)
            ! Each mode scaled so that the largest of its nodal displacements |u| and of L
            ! |theta| (L the system's extent) is 1 over the system's rods: a torsion mode,
            ! whose centreline does not move, has rotations of at most 1 / L.
            allocate(scale(n), source=0.0_rk)
            extent = 0.0_rk
            do m = 1, size(system%members)
                call nodal_shapes(system, m, x, shapes, position, displacement, rotation)
                if (size(position, 2) > 0) extent = max(extent, maxval(maxval(position, dim=2) - &
                    minval(position, dim=2)))
            end do
            do m = 1, size(system%members)
                call nodal_shapes(system, m, x, shapes, position, displacement, rotation)
                if (size(position, 2) == 0) cycle
                scale = max(scale, maxval(norm2(displacement, dim=1), dim=1), &
                    extent * maxval(norm2(rotation, dim=1), dim=1))
            end do
            where (scale <= 0.0_rk) scale = 1.0_rk
            n_shown = 0
            do m = 1, size(system%members)
                call nodal_shapes(system, m, x, shapes, position, displacement, rotation)
                ! A formulation without node access (ph_planar) gives frequencies only.
                if (size(position, 2) == 0) cycle
                n_shown = n_shown + 1
                displacement = displacement / spread(spread(scale, 1, size(displacement, 2)), 1, 3)
                rotation = rotation / spread(spread(scale, 1, size(rotation, 2)), 1, 3)
                associate (shown => rods(n_shown))
                    shown%name = system%members(m)%name
                    shown%group = group // '/' // shown%name
                    shown%n_nodes = size(position, 2)
                    if (allocated(modes%load_factor)) then
                        shown%frequency = modes%load_factor(1:n)
                    else
                        shown%frequency = modes%omega(1:n) / (2.0_rk * pi)
                    end if
                end associate
                call file%create_group(rods(n_shown)%group, err)
                if (allocated(err)) exit body
                call file%write_dataset(rods(n_shown)%group // '/position', position, &
                    unit_in_system('m', units), 'reference position of each node, the state ' // &
                    'the modes are about, [node, xyz]', err)
                if (allocated(err)) exit body
                call file%write_dataset(rods(n_shown)%group // '/displacement', displacement, &
                    unit_in_system('m', units), 'mode shape: the nodal displacement of each ' // &
                    'mode, scaled so that the largest of |displacement| and L |rotation| over ' // &
                    'the system is 1 (L its extent), [mode, node, xyz]', err)
                if (allocated(err)) exit body
                call file%write_dataset(rods(n_shown)%group // '/rotation', rotation, 'rad', &
                    'mode shape: the infinitesimal rotation of each node''s cross-section, ' // &
                    'spatial components, scaled as displacement, [mode, node, xyz]', err)
                if (allocated(err)) exit body
            end do
        end block body
        rods = rods(1:n_shown)
        call file%close(close_err)
        if (.not. allocated(err) .and. allocated(close_err)) call move_alloc(close_err, err)
    end subroutine write_modes

    !> Member m's node positions in x (3, nodes) and every mode's nodal displacement and
    !> rotation (3, nodes, modes), spatial components: the centreline part of the eigenvector,
    !> and its rotation part as the formulation's coordinates give it (rod_nodes_t): a rotation
    !> vector psi turns by A(psi) T(psi) dpsi (se3_pg: T(psi) psi' is the body angular
    !> velocity, methods/se3_petrov_galerkin.md eq. 39), directors by 1/2 sum_i d_i x dd_i
    !> (the infinitesimal rotation that moves orthonormal directors by dd_i = theta x d_i). A
    !> held coordinate does not move.
    subroutine nodal_shapes(system, m, x, shapes, position, displacement, rotation)
        type(rod_system_t), intent(in) :: system
        integer, intent(in) :: m
        !> The modes' eigenvectors, real (node_phase).
        real(rk), intent(in) :: x(:), shapes(:, :)
        real(rk), allocatable, intent(out) :: position(:, :), displacement(:, :, :), &
            rotation(:, :, :)
        real(rk) :: q(max_node_coordinates), dq(max_node_coordinates, size(shapes, 2))
        real(rk) :: turn(3, 3)
        integer :: k, i, j, uo, n_coordinates, at, n_modes
        associate (place => system%layout%members(m), nodes => system%layout%members(m)%nodes)
            uo = place%unknown_offset
            n_coordinates = nodes%n_coordinates
            n_modes = size(shapes, 2)
            allocate(position(3, nodes%n_nodes), displacement(3, nodes%n_nodes, n_modes), &
                rotation(3, nodes%n_nodes, n_modes), source=0.0_rk)
            do k = 1, nodes%n_nodes
                q = 0.0_rk
                q(1:n_coordinates) = system%layout%node_state(m, k, x, n_coordinates)
                dq = 0.0_rk
                do i = 1, n_coordinates
                    if (nodes%unknown(i, k) > 0) dq(i, :) = shapes(uo + nodes%unknown(i, k), :)
                end do
                position(:, k) = q(1:3)
                displacement(:, k, :) = dq(1:3, :)
                if (nodes%rotation_vector_at > 0) then
                    at = nodes%rotation_vector_at
                    turn = matmul(exp_so3(q(at:at + 2)), tangent_so3(q(at:at + 2)))
                    rotation(:, k, :) = matmul(turn, dq(at:at + 2, :))
                else if (nodes%directors_at > 0) then
                    at = nodes%directors_at
                    do j = 0, 2
                        do i = 1, n_modes
                            rotation(:, k, i) = rotation(:, k, i) + 0.5_rk * &
                                matmul(hat(q(at + 3 * j:at + 3 * j + 2)), &
                                dq(at + 3 * j:at + 3 * j + 2, i))
                        end do
                    end do
                end if
            end do
        end associate
    end subroutine nodal_shapes

    !> The modes' eigenvectors made real on the node coordinates: x = re + i im turned by the
    !> phase theta that makes the nodes' part of Re(exp(-i theta) x) largest, theta = 1/2
    !> atan2(2 re.im, |re|^2 - |im|^2) over the node coordinates. A first-order mode's
    !> velocities are a quarter period from its positions, so the vector's largest entry
    !> (a velocity, for a fast mode) gives the wrong phase: ph_director's torsion mode came
    !> out as noise. A second-order mode's vector is real already.
    function node_phase(system, modes) result(shapes)
        type(rod_system_t), intent(in) :: system
        type(modes_t), intent(in) :: modes
        real(rk), allocatable :: shapes(:, :)
        logical, allocatable :: shown(:)
        real(rk) :: a, b, c, theta
        integer :: m, k, i, j
        allocate(shown(size(modes%shape, 1)), source=.false.)
        do m = 1, size(system%members)
            associate (place => system%layout%members(m), nodes => system%layout%members(m)%nodes)
                do k = 1, nodes%n_nodes
                    do i = 1, nodes%n_coordinates
                        if (nodes%unknown(i, k) > 0) shown(place%unknown_offset + &
                            nodes%unknown(i, k)) = .true.
                    end do
                end do
            end associate
        end do
        allocate(shapes(size(modes%shape, 1), modes%n))
        do j = 1, modes%n
            associate (re => modes%shape(:, j), im => modes%shape_im(:, j))
                a = sum(re**2, mask=shown)
                b = sum(im**2, mask=shown)
                c = sum(re * im, mask=shown)
                theta = 0.5_rk * atan2(2.0_rk * c, a - b)
                shapes(:, j) = re * cos(theta) + im * sin(theta)
            end associate
        end do
    end function node_phase

end module rs_app_run_modes
