#include "rs_assert.h"
!> What the tests of the formulation contract share (test_formulations_conformance,
!> test_formulation_traits, test_ph_director): a parsed cantilever of any formulation, the
!> assembled step Jacobian at a perturbed unknown, and central differences of the step
!> residual.
module rs_test_formulation_fixture
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, error_list_t
    use rs_test_assert, only: assert_true, assert_equal
    use rs_model_scene, only: scene_t
    use rs_io_input_file, only: parse_scene
    use rs_formulations_formulation, only: rod_formulation_t, state_valid
    use rs_system_rod_system, only: rod_system_t
    implicit none
    private

    public :: cantilever_text, init_cantilever, init_from_text, init_cantilever_system, &
        jacobian_at, central_differences, dense_jacobian

    !> The step the Jacobians are taken on.
    real(rk), parameter, public :: fixture_t_n = 0.3_rk, fixture_h = 0.05_rk

    character(len=*), parameter :: nl = new_line('a')

contains

    !> A cantilever along x in the x-z plane (planar formulations take it as it is): clamped at
    !> s = 0 (se3_strand: free at s = L, as it must be), an end force and a moment about y,
    !> gravity and a load per length along -z, so that every load term enters the step
    !> residual; dynamic unless `quasistatic`, stresses condensed if `condense`.
    function cantilever_text(name, n_elements, quasistatic, condense) result(text)
        character(len=*), intent(in) :: name
        integer, intent(in) :: n_elements
        logical, intent(in) :: quasistatic, condense
        character(len=:), allocatable :: text
        character(len=12) :: count_text
        write(count_text, '(i0)') n_elements
        text = '&time t_end = 1, dt = 0.05'
        if (quasistatic) text = text // ', quasistatic = .true.'
        text = text // ' /' // nl
        if (condense) text = text // '&solver condense_stresses = .true. /' // nl
        text = text // &
            "&rod name = 'beam', formulation = '" // trim(name) // "', n_elements = " // &
            trim(count_text) // ', length = 2,' // nl // &
            '     EA = 1e3, GA1 = 5e2, GA2 = 5e2, EI1 = 2, EI2 = 3, GJ = 1.5,' // nl // &
            '     rhoA = 1, rhoI1 = 0.1, rhoI2 = 0.15 /' // nl // &
            "&bc rod = 'beam', end = 'start', kind = 'clamped' /" // nl // &
            "&load rod = 'beam', where = 'end', force = 0.5, 0, -1, moment = 0, 0.4, 0 /" // nl // &
            "&load rod = 'beam', where = 'distributed', force = 0, 0, -0.2 /" // nl // &
            "&load where = 'gravity', acceleration = 0, 0, -9.81 /" // nl
        if (trim(name) == 'se3_strand') text = text // "&bc rod = 'beam', end = 'end', kind = 'free' /" // nl
    end function cantilever_text

    !> Init `rod` (allocated as formulation `name`) on cantilever_text; `ok` false (and the
    !> failed check recorded) if the scene does not parse or the rod cannot be built.
    subroutine init_cantilever(rod, name, n_elements, ok, quasistatic, condense)
        class(rod_formulation_t), intent(inout) :: rod
        character(len=*), intent(in) :: name
        integer, intent(in) :: n_elements
        logical, intent(out) :: ok
        logical, intent(in), optional :: quasistatic, condense
        logical :: statics, condensed
        statics = .false.
        condensed = .false.
        if (present(quasistatic)) statics = quasistatic
        if (present(condense)) condensed = condense
        call init_from_text(rod, cantilever_text(name, n_elements, statics, condensed), name, ok)
    end subroutine init_cantilever

    !> Init `rod` on its scene `text` (rod 1 of it, alone); `ok` false (and the failed check,
    !> named by `label`, recorded) if the scene does not parse or the rod cannot be built.
    subroutine init_from_text(rod, text, label, ok)
        class(rod_formulation_t), intent(inout) :: rod
        character(len=*), intent(in) :: text, label
        logical, intent(out) :: ok
        type(scene_t) :: scene
        type(error_list_t) :: errors
        type(error_t), allocatable :: err
        call parse_scene(text, 'cantilever.nml', scene, errors)
        CHECK_EQUAL(errors%count, 0, label // ': the scene parses: ' // errors%joined())
        ok = errors%count == 0
        if (.not. ok) return
        call rod%init(scene, [1], err)
        CHECK_TRUE(.not. allocated(err), label // ': init')
        ok = .not. allocated(err)
        if (.not. ok) write(*, '(a)') '  ' // err%describe()
    end subroutine init_from_text

    !> The system layer's system (rs_system_rod_system) of the same cantilever.
    subroutine init_cantilever_system(system, name, n_elements, ok)
        type(rod_system_t), intent(inout) :: system
        character(len=*), intent(in) :: name
        integer, intent(in) :: n_elements
        logical, intent(out) :: ok
        type(scene_t) :: scene
        type(error_list_t) :: errors
        type(error_t), allocatable :: err
        call parse_scene(cantilever_text(name, n_elements, .false., .false.), 'cantilever.nml', &
            scene, errors)
        CHECK_EQUAL(errors%count, 0, name // ': the scene parses: ' // errors%joined())
        ok = errors%count == 0
        if (.not. ok) return
        call system%init(scene, [1], err)
        CHECK_TRUE(.not. allocated(err), name // ': system init')
        ok = .not. allocated(err)
        if (.not. ok) write(*, '(a)') '  ' // err%describe()
    end subroutine init_cantilever_system

    !> The step Jacobian (CSR) on the fixture's step from the initial state x_n, at the
    !> prediction y moved by a random 0.01 (no entry vanishes by the symmetry of the start,
    !> and the inertia enters).
    subroutine jacobian_at(rod, x_n, y, row_ptr, cols, values)
        class(rod_formulation_t), intent(inout) :: rod
        real(rk), allocatable, intent(out) :: x_n(:), y(:), values(:)
        integer, allocatable, intent(out) :: row_ptr(:), cols(:)
        real(rk), allocatable :: noise(:)
        integer :: status
        allocate(x_n(rod%n_state()), y(rod%n_unknown()), noise(rod%n_unknown()))
        call rod%initial_state(x_n)
        call rod%predictor(fixture_t_n, fixture_h, x_n, y)
        call random_number(noise)
        y = y + 0.01_rk * (noise - 0.5_rk)
        call rod%jacobian_pattern(row_ptr, cols)
        allocate(values(size(cols)))
        call rod%step_jacobian(fixture_t_n, fixture_h, x_n, y, values, status)
        CHECK_EQUAL(status, state_valid, 'Jacobian status')
    end subroutine jacobian_at

    !> dF/dY by central differences of the step residual with step `step`, column by column.
    function central_differences(rod, t_n, h, x_n, y, step) result(difference)
        class(rod_formulation_t), intent(inout) :: rod
        real(rk), intent(in) :: t_n, h, x_n(:), step
        real(rk), intent(inout) :: y(:)
        real(rk), allocatable :: difference(:, :)
        real(rk), allocatable :: f_plus(:), f_minus(:)
        integer :: n, j, status
        n = size(y)
        allocate(difference(n, n), f_plus(n), f_minus(n))
        do j = 1, n
            y(j) = y(j) + step
            call rod%step_residual(t_n, h, x_n, y, f_plus, status)
            y(j) = y(j) - 2.0_rk * step
            call rod%step_residual(t_n, h, x_n, y, f_minus, status)
            y(j) = y(j) + step
            difference(:, j) = (f_plus - f_minus) / (2.0_rk * step)
        end do
    end function central_differences

    !> The CSR matrix as a dense n x n one (zero outside the pattern).
    pure function dense_jacobian(row_ptr, cols, values) result(dense)
        integer, intent(in) :: row_ptr(:), cols(:)
        real(rk), intent(in) :: values(:)
        real(rk), allocatable :: dense(:, :)
        integer :: n, row, k
        n = size(row_ptr) - 1
        allocate(dense(n, n), source=0.0_rk)
        do row = 1, n
            do k = row_ptr(row) + 1, row_ptr(row + 1)
                dense(row, cols(k) + 1) = values(k)
            end do
        end do
    end function dense_jacobian

end module rs_test_formulation_fixture
