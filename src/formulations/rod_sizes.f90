!> The sizes of one rod as a run builds it (unknowns, state, Jacobian non-zeros), found without
!> building the rod at its full size (issue 21 item 17: the plan of --check-input built every
!> rod, ~46 KB per element, so the check of a 10^6-element scene was killed for memory).
!>
!> Every element of a rod's uniform mesh is alike and only the two end nodes are special
!> (supports, end loads), so each size is an affine function of the number of elements E once
!> E >= 2: size(E) = size(a) + (E - a) (size(a + 1) - size(a)). The rod is built by its own
!> formulation (an object of the type of `mold`, from rs_formulations_factory or the
!> formulation's own plan, which the factory's registry depends on) alone, with its supports, loads and actuators, at
!> a = 3 and a + 1 = 4 elements, and the sizes are read off the built objects and extended to
!> E; a rod of at most 4 elements is built as it is. Joints, end plates and contact are left
!> out: their multipliers and pairs are a few per rod end, not per element.
module rs_formulations_rod_sizes
    use, intrinsic :: iso_fortran_env, only: int64
    use rs_core_error, only: error_t
    use rs_model_scene, only: scene_t
    use rs_formulations_formulation, only: rod_formulation_t
    implicit none
    private

    public :: rod_sizes_of, single_rod_scene

    !> Element counts of the two small builds (both >= 2, so the ends are distinct elements).
    integer, parameter :: small_elements = 3

    !> Sizes of one rod at its scene's element count.
    type, public :: rod_sizes_t
        integer(int64) :: n_elements = 0
        !> Newton unknowns Y of a step and the length of the state X.
        integer(int64) :: n_unknown = 0
        integer(int64) :: n_state = 0
        !> Non-zeros of the Jacobian pattern dF/dY.
        integer(int64) :: n_nonzeros = 0
    end type rod_sizes_t

contains

    !> The sizes of rod `i` of the resolved, checked `scene`, built as objects of the dynamic
    !> type of `mold` (its formulation); `err` if the rod cannot be built.
    subroutine rod_sizes_of(scene, i, sizes, err, mold)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i
        type(rod_sizes_t), intent(out) :: sizes
        type(error_t), allocatable, intent(out) :: err
        class(rod_formulation_t), intent(in) :: mold
        type(rod_sizes_t) :: at_a, at_b
        integer(int64) :: e
        e = scene%rods(i)%n_elements
        if (e <= small_elements + 1) then
            call built_sizes(scene, i, int(e), mold, sizes, err)
            return
        end if
        call built_sizes(scene, i, small_elements, mold, at_a, err)
        if (allocated(err)) return
        call built_sizes(scene, i, small_elements + 1, mold, at_b, err)
        if (allocated(err)) return
        sizes%n_elements = e
        sizes%n_unknown = extended(at_a%n_unknown, at_b%n_unknown)
        sizes%n_state = extended(at_a%n_state, at_b%n_state)
        sizes%n_nonzeros = extended(at_a%n_nonzeros, at_b%n_nonzeros)
    contains
        pure integer(int64) function extended(at_small, at_next)
            integer(int64), intent(in) :: at_small, at_next
            extended = at_small + (e - small_elements) * (at_next - at_small)
        end function extended
    end subroutine rod_sizes_of

    !> Build rod `i` alone with `n_elements` elements and read its sizes off the object.
    subroutine built_sizes(scene, i, n_elements, mold, sizes, err)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i, n_elements
        class(rod_formulation_t), intent(in) :: mold
        type(rod_sizes_t), intent(out) :: sizes
        type(error_t), allocatable, intent(out) :: err
        class(rod_formulation_t), allocatable :: rod
        integer, allocatable :: row_ptr(:), cols(:)
        allocate(rod, mold=mold)
        call rod%init(single_rod_scene(scene, i, n_elements), [1], err)
        if (allocated(err)) return
        call rod%jacobian_pattern(row_ptr, cols)
        sizes%n_elements = n_elements
        sizes%n_unknown = rod%n_unknown()
        sizes%n_state = rod%n_state()
        sizes%n_nonzeros = size(cols)
    end subroutine built_sizes

    !> A scene of rod `i` alone with `n_elements` elements: its &bc, &actuator groups and the
    !> &load groups that act on it (by name, or on every rod), the single groups of `scene`; no
    !> joints, plates, contact, sweeps or source text. Only the groups of this rod are copied,
    !> so building every rod of a large scene this way stays linear in its groups.
    function single_rod_scene(scene, i, n_elements) result(single)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i, n_elements
        type(scene_t) :: single
        integer :: k
        associate (name => scene%rods(i)%name)
            single%source_file = ''
            if (allocated(scene%source_file)) single%source_file = scene%source_file
            single%source_text = ''
            single%run = scene%run
            single%time = scene%time
            single%solver = scene%solver
            single%output = scene%output
            single%rods = [scene%rods(i)]
            single%rods(1)%n_elements = n_elements
            allocate(single%bcs(0), single%loads(0), single%actuators(0))
            if (allocated(scene%bcs)) single%bcs = pack(scene%bcs, &
                [(scene%bcs(k)%rod == name, k = 1, size(scene%bcs))])
            if (allocated(scene%loads)) single%loads = pack(scene%loads, &
                [(scene%loads(k)%rod == name .or. len_trim(scene%loads(k)%rod) == 0, &
                k = 1, size(scene%loads))])
            if (allocated(scene%actuators)) single%actuators = pack(scene%actuators, &
                [(scene%actuators(k)%rod == name, k = 1, size(scene%actuators))])
            allocate(single%joints(0), single%plates(0), single%sweeps(0), single%segments(0))
            if (allocated(scene%segments)) single%segments = pack(scene%segments, &
                [(scene%segments(k)%rod == name, k = 1, size(scene%segments))])
        end associate
    end function single_rod_scene

end module rs_formulations_rod_sizes
