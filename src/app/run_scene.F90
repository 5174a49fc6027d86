#include "rs_macros.h"
!> The run of a validated scene (DESIGN.md §5 and §7): rods are dealt to ranks, each rank runs
!> its rods with no communication, the records are gathered to rank 0 after the time loop and
!> rank 0 writes the result file. A rod that fails stops only itself; what was computed is
!> still written and the run ends with status 1.
module rs_app_run_scene
    use, intrinsic :: iso_fortran_env, only: error_unit
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_core_logger, only: log_info
    use rs_core_strings, only: str, str_significant
    use rs_core_timer, only: wall_time
    use rs_model_scene, only: scene_t
    use rs_model_rod_history, only: rod_history_t
    use rs_parallel_mpi_env, only: world_rank, world_size, send_array, receive_array, &
        any_rank_true, mpi_library_version
    use rs_io_result_file, only: result_meta_t, write_result_file
    use rs_io_hdf5_file, only: hdf5_file_t
    use rs_io_scene_writer, only: resolved_scene_text
    use rs_solver_petsc_env, only: petsc_version
    use rs_solver_rod_stepper, only: petsc_apply_options, petsc_options_text
    use rs_solver_rod_run, only: run_rod
    implicit none
    private

    public :: run_scene

    integer, parameter :: tag_header = 101, tag_values = 102

contains

    !> Run every rod of `scene` and write the result file; `err` is set (on every rank) if any
    !> rod failed or the file could not be written.
    subroutine run_scene(scene, command_line, err)
        type(scene_t), intent(in) :: scene
        character(len=*), intent(in) :: command_line
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: message
        type(rod_history_t), allocatable :: histories(:)
        type(error_t), allocatable :: rod_err, write_err
        type(result_meta_t) :: meta
        integer, allocatable :: header(:)
        real(rk), allocatable :: values(:)
        real(rk) :: started
        integer :: i, owner
        logical :: failed

        call petsc_apply_options(scene_options(scene), trim(scene%solver%petsc_options), err)
        RS_RETURN_IF_ERROR(err)
        ! Nothing computed may be lost to an output path that cannot be written: try it first.
        if (world_rank() == 0) call probe_output(trim(scene%output%path), write_err)
        if (any_rank_true(allocated(write_err))) then
            if (allocated(write_err)) then
                call move_alloc(write_err, err)
            else
                RS_SET_ERROR(err, 'run_scene', 'the output file cannot be written (see rank 0)')
            end if
            return
        end if
        started = wall_time()
        allocate(histories(size(scene%rods)))
        failed = .false.
        do i = 1, size(scene%rods)
            if (rod_owner(i) /= world_rank()) cycle
            call run_rod(scene, i, histories(i), rod_err)
            if (allocated(rod_err)) then
                failed = .true.
                write(error_unit, '(a)') 'rodsolve: rod ''' // trim(scene%rods(i)%name) // &
                    ''' (rank ' // str(world_rank()) // '): ' // rod_err%describe()
                flush(error_unit)
            end if
        end do

        ! Gather the records to rank 0 (DESIGN.md §7: rank 0 writes).
        do i = 1, size(scene%rods)
            owner = rod_owner(i)
            if (owner == 0) cycle
            if (world_rank() == owner) then
                call histories(i)%pack(header, values)
                call send_array(header, 0, tag_header)
                call send_array(values, 0, tag_values)
                call histories(i)%free()
            else if (world_rank() == 0) then
                call receive_array(header, owner, tag_header)
                call receive_array(values, owner, tag_values)
                call histories(i)%unpack(header, values)
            end if
        end do

        if (world_rank() == 0) then
            meta%command_line = command_line
            meta%n_ranks = world_size()
            meta%petsc_version = petsc_version()
            meta%mpi_version = mpi_library_version()
            meta%input_text = scene%source_text
            meta%input_resolved = resolved_scene_text(scene)
            meta%petsc_options = petsc_options_text()
            meta%title = trim(scene%run%title)
            call write_result_file(trim(scene%output%path), meta, histories, write_err)
            if (.not. allocated(write_err)) call log_info('rodsolve: ' // str(size(histories)) // &
                ' rod(s) in ' // str_significant(wall_time() - started, 3) // ' s; results in ' // &
                trim(scene%output%path))
        end if
        if (any_rank_true(allocated(write_err))) then
            if (allocated(write_err)) then
                call move_alloc(write_err, err)
            else
                RS_SET_ERROR(err, 'run_scene', 'the result file could not be written (see rank 0)')
            end if
            return
        end if
        if (any_rank_true(failed)) then
            message = 'a rod failed (message above); what was computed is in ' // &
                trim(scene%output%path)
            RS_SET_ERROR(err, 'run_scene', message)
        end if
    end subroutine run_scene

    !> Create (and close) the result file, so that a path that cannot be written is reported
    !> before the run rather than after it.
    subroutine probe_output(path, err)
        character(len=*), intent(in) :: path
        type(error_t), allocatable, intent(out) :: err
        type(hdf5_file_t) :: file
        call file%create(path, err)
        RS_RETURN_IF_ERROR(err)
        call file%close(err)
    end subroutine probe_output

    !> Rank that runs rod i: round robin, so independent rods spread over the ranks.
    integer function rod_owner(i)
        integer, intent(in) :: i
        rod_owner = mod(i - 1, world_size())
    end function rod_owner

    !> PETSc options that follow from the scene (DESIGN.md §3): the Newton stopping rule of the
    !> method document with PETSc's relative tests off, and MUMPS LU. `petsc_options` and the
    !> command line override them.
    function scene_options(scene) result(options)
        type(scene_t), intent(in) :: scene
        character(len=:), allocatable :: options
        options = '-snes_atol ' // str(scene%solver%newton_atol) // ' -snes_rtol ' // &
            str(scene%solver%newton_rtol) // ' -snes_stol 0 -snes_max_it ' // &
            str(scene%solver%max_newton) // ' -snes_max_funcs 1000000 -ksp_type preonly ' // &
            '-pc_type lu -pc_factor_mat_solver_type mumps -mat_mumps_icntl_14 50'
    end function scene_options

end module rs_app_run_scene
