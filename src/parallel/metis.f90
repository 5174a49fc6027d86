!> Graph partitioning with METIS 5 through its C API (DESIGN.md §5). Debian's METIS 5.1 uses
!> 32-bit idx_t and real_t (checked by CMake); it dies with SIGFPE for nparts = 1, so one part is
!> answered here without calling it.
module rs_parallel_metis
    use, intrinsic :: iso_c_binding, only: c_int32_t, c_float, c_ptr, c_null_ptr, c_loc, c_int
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: str
    implicit none
    private

    public :: partition_graph, metis_version

    integer, parameter :: metis_ok = 1
    integer, parameter :: metis_noptions = 40
    !> Position of METIS_OPTION_NUMBERING in METIS 5.1's options enum (metis.h).
    integer, parameter :: metis_option_numbering = 17

    interface
        integer(c_int) function metis_part_graph_kway(nvtxs, ncon, xadj, adjncy, vwgt, vsize, &
                adjwgt, nparts, tpwgts, ubvec, options, objval, part) bind(C, name='METIS_PartGraphKway')
            import :: c_int32_t, c_ptr, c_int
            integer(c_int32_t), intent(in) :: nvtxs, ncon, nparts
            integer(c_int32_t), intent(in) :: xadj(*), adjncy(*)
            type(c_ptr), value :: vwgt, vsize, adjwgt, tpwgts, ubvec
            integer(c_int32_t), intent(in) :: options(*)
            integer(c_int32_t), intent(out) :: objval
            integer(c_int32_t), intent(out) :: part(*)
        end function metis_part_graph_kway

        integer(c_int) function metis_set_default_options(options) bind(C, name='METIS_SetDefaultOptions')
            import :: c_int32_t, c_int
            integer(c_int32_t), intent(out) :: options(*)
        end function metis_set_default_options

        subroutine rs_metis_version(major, minor, subminor) bind(C, name='rs_metis_version')
            import :: c_int
            integer(c_int), intent(out) :: major, minor, subminor
        end subroutine rs_metis_version
    end interface

contains

    !> Partition the graph given in CSR form (0-based `xadj`/`adjncy`, as METIS wants) into
    !> `nparts` parts balancing `vertex_weights`; `part(i)` is the 0-based part of vertex i.
    subroutine partition_graph(xadj, adjncy, vertex_weights, nparts, part, err)
        integer(c_int32_t), intent(in) :: xadj(:), adjncy(:)
        integer(c_int32_t), intent(in), target :: vertex_weights(:)
        integer, intent(in) :: nparts
        integer(c_int32_t), intent(out) :: part(:)
        type(error_t), allocatable, intent(out) :: err
        integer(c_int32_t) :: options(metis_noptions), objval, nvtxs
        integer(c_int) :: status
        nvtxs = int(size(xadj) - 1, c_int32_t)
        if (nparts < 1 .or. size(part) /= nvtxs .or. size(vertex_weights) /= nvtxs) then
            call set_error(err, 'partition_graph: inconsistent sizes or nparts < 1', &
                'partition_graph', __FILE__, __LINE__)
            return
        end if
        if (nparts == 1 .or. nvtxs <= 1) then
            part = 0
            return
        end if
        status = metis_set_default_options(options)
        options(metis_option_numbering + 1) = 0   ! C-style (0-based) vertex numbers
        status = metis_part_graph_kway(nvtxs, 1_c_int32_t, xadj, adjncy, c_loc(vertex_weights), &
            c_null_ptr, c_null_ptr, int(nparts, c_int32_t), c_null_ptr, c_null_ptr, options, objval, part)
        if (status /= metis_ok) then
            call set_error(err, 'METIS_PartGraphKway failed with status ' // str(int(status)), &
                'partition_graph', __FILE__, __LINE__)
        end if
    end subroutine partition_graph

    !> "major.minor.subminor" of the METIS header rodsolve was built with.
    function metis_version() result(text)
        character(len=:), allocatable :: text
        integer(c_int) :: major, minor, subminor
        call rs_metis_version(major, minor, subminor)
        text = str(int(major)) // '.' // str(int(minor)) // '.' // str(int(subminor))
    end function metis_version

end module rs_parallel_metis
