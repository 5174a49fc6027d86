#include "rs_assert.h"
!> The traits of each formulation (formulation_traits_t, issue 22 item 2) against what they
!> claim about the step problem, checked on the assembled Jacobian of a parsed cantilever:
!>   - native_lu (PETSc's LU without pivoting): every diagonal entry of dF/dY is in the pattern
!>     and non-zero. Where a formulation says no (ph_director's director multipliers, ph_planar's
!>     uncondensed quasistatic PH-EM with its zero (x, y) diagonals), a zero diagonal is found,
!>     so the check tells the two apart;
!>   - linear_step (one linear solve per step): F is affine in Y, F(Y2) = F(Y1) + J (Y2 - Y1)
!>     to round-off with the same J at Y1 and Y2; se3_pg's nonlinear F fails the same check by
!>     orders of magnitude;
!>   - banded_unknowns (the LU keeps the order): the half bandwidth of the pattern does not
!>     grow with the number of elements;
!>   - the endpoint solves and the energy scheme follow quasistatic or dynamic as each
!>     formulation's method document says (DESIGN.md §3, "Quasistatics"; the energy sentinel).
module rs_test_formulation_traits
    use rs_core_kinds, only: rk
    use rs_test_assert, only: run_test, assert_true, assert_equal
    use rs_formulations_formulation, only: rod_formulation_t, formulation_traits_t
    use rs_formulations_energy_sentinel, only: energy_consistent, energy_dissipative, &
        energy_unchecked
    use rs_ph_director, only: ph_director_t
    use rs_ph_planar, only: ph_planar_t
    use rs_se3_pg, only: se3_pg_t
    use rs_se3_strand, only: se3_strand_t
    use rs_test_random, only: set_random_seed
    use rs_test_formulation_fixture, only: init_cantilever, jacobian_at, fixture_t_n, fixture_h
    implicit none
    private

    public :: run_all_tests

contains

    subroutine run_all_tests()
        call run_test('ph_director', test_ph_director)
        call run_test('ph_planar', test_ph_planar)
        call run_test('cl_em_planar', test_cl_em_planar)
        call run_test('se3_pg', test_se3_pg)
        call run_test('se3_strand', test_se3_strand)
    end subroutine run_all_tests

    !> Chain LU (zero diagonals of the multipliers), backtracking Newton; energy-consistent
    !> dynamics; quasistatic runs end with a continued endpoint equilibrium (they keep their
    !> stresses as unknowns, so Y has the layout of X).
    subroutine test_ph_director()
        type(ph_director_t) :: dynamic, quasistatic
        type(formulation_traits_t) :: traits
        call build(dynamic, 'ph_director', 4, .false.)
        traits = dynamic%traits()
        call check_flags(traits, 'ph_director, dynamic', native_lu=.false., banded=.false., &
            full_newton=.false., linear=.false., endpoint=.false., continued=.false., &
            energy=energy_consistent)
        call check_native_lu(dynamic, traits, 'ph_director, dynamic')
        CHECK_TRUE(smallest_diagonal(dynamic) == 0.0_rk, 'ph_director: a zero diagonal (multipliers), so no native LU')
        call build(quasistatic, 'ph_director', 4, .true.)
        traits = quasistatic%traits()
        call check_flags(traits, 'ph_director, quasistatic', native_lu=.false., banded=.false., &
            full_newton=.false., linear=.false., endpoint=.true., continued=.true., &
            energy=energy_unchecked)
    end subroutine test_ph_director

    !> PETSc's LU where the diagonal is non-zero (dynamic: the mass), the chain LU for the
    !> uncondensed quasistatic PH-EM (zero (x, y) diagonals); full Newton always.
    subroutine test_ph_planar()
        type(ph_planar_t) :: dynamic, quasistatic, condensed
        type(formulation_traits_t) :: traits
        call build(dynamic, 'ph_planar', 4, .false.)
        traits = dynamic%traits()
        call check_flags(traits, 'ph_planar, dynamic', native_lu=.true., banded=.false., &
            full_newton=.true., linear=.false., endpoint=.false., continued=.false., &
            energy=energy_consistent)
        call check_native_lu(dynamic, traits, 'ph_planar, dynamic')
        call build(quasistatic, 'ph_planar', 4, .true.)
        traits = quasistatic%traits()
        call check_flags(traits, 'ph_planar, quasistatic', native_lu=.false., banded=.false., &
            full_newton=.true., linear=.false., endpoint=.true., continued=.true., &
            energy=energy_unchecked)
        call check_native_lu(quasistatic, traits, 'ph_planar, quasistatic')
        CHECK_TRUE(smallest_diagonal(quasistatic) == 0.0_rk, 'ph_planar, quasistatic PH-EM: a zero diagonal, so no native LU')
        call build(condensed, 'ph_planar', 4, .true., condense=.true.)
        traits = condensed%traits()
        CHECK_TRUE(traits%native_lu, 'ph_planar, condensed quasistatic: native LU')
        call check_native_lu(condensed, traits, 'ph_planar, condensed quasistatic')
    end subroutine test_ph_planar

    !> The displacement scheme has a non-zero diagonal quasistatic too: PETSc's LU.
    subroutine test_cl_em_planar()
        type(ph_planar_t) :: dynamic, quasistatic
        type(formulation_traits_t) :: traits
        call build(dynamic, 'cl_em_planar', 4, .false.)
        traits = dynamic%traits()
        call check_flags(traits, 'cl_em_planar, dynamic', native_lu=.true., banded=.false., &
            full_newton=.true., linear=.false., endpoint=.false., continued=.false., &
            energy=energy_consistent)
        call check_native_lu(dynamic, traits, 'cl_em_planar, dynamic')
        call build(quasistatic, 'cl_em_planar', 4, .true.)
        traits = quasistatic%traits()
        CHECK_TRUE(traits%native_lu, 'cl_em_planar, quasistatic: native LU')
        call check_native_lu(quasistatic, traits, 'cl_em_planar, quasistatic')
    end subroutine test_cl_em_planar

    !> Full Newton (methods §7.2), everything else default; its F is not affine in Y.
    subroutine test_se3_pg()
        type(se3_pg_t) :: rod
        type(formulation_traits_t) :: traits
        real(rk) :: defect
        call build(rod, 'se3_pg', 4, .false.)
        traits = rod%traits()
        call check_flags(traits, 'se3_pg', native_lu=.false., banded=.false., full_newton=.true., &
            linear=.false., endpoint=.false., continued=.false., energy=energy_unchecked)
        call check_native_lu(rod, traits, 'se3_pg')
        defect = affine_defect(rod)
        write(*, '(a,es10.3)') '  se3_pg: affine defect ', defect
        CHECK_TRUE(defect > 1.0e-6_rk, 'se3_pg: F is not affine in Y (the check sees it)')
    end subroutine test_se3_pg

    !> PETSc's LU in the natural order on a step problem that is one linear solve; the
    !> semi-implicit scheme dissipates.
    subroutine test_se3_strand()
        type(se3_strand_t) :: rod, longer
        type(formulation_traits_t) :: traits
        real(rk) :: defect
        call build(rod, 'se3_strand', 4, .false.)
        traits = rod%traits()
        call check_flags(traits, 'se3_strand', native_lu=.true., banded=.true., full_newton=.false., &
            linear=.true., endpoint=.false., continued=.false., energy=energy_dissipative)
        call check_native_lu(rod, traits, 'se3_strand')
        ! An affine F leaves only the round-off of the products and sums (2e-16 measured, a few
        ! units of 1e-16); the bound 1e-14 is 60 times that, and far below se3_pg's defect.
        defect = affine_defect(rod)
        write(*, '(a,es10.3)') '  se3_strand: affine defect ', defect
        CHECK_TRUE(defect <= 1.0e-14_rk, 'se3_strand: F affine in Y with a constant J (linear_step)')
        call build(longer, 'se3_strand', 8, .false.)
        CHECK_EQUAL(half_bandwidth(longer), half_bandwidth(rod), 'se3_strand: the band does not grow with the elements (banded_unknowns)')
    end subroutine test_se3_strand

    ! ---- Checks --------------------------------------------------------------------------------

    subroutine check_flags(traits, what, native_lu, banded, full_newton, linear, endpoint, &
            continued, energy)
        type(formulation_traits_t), intent(in) :: traits
        character(len=*), intent(in) :: what
        logical, intent(in) :: native_lu, banded, full_newton, linear, endpoint, continued
        integer, intent(in) :: energy
        CHECK_TRUE(traits%native_lu .eqv. native_lu, what // ': native_lu')
        CHECK_TRUE(traits%banded_unknowns .eqv. banded, what // ': banded_unknowns')
        CHECK_TRUE(traits%full_newton .eqv. full_newton, what // ': full_newton')
        CHECK_TRUE(traits%linear_step .eqv. linear, what // ': linear_step')
        CHECK_TRUE(traits%wants_endpoint_solve .eqv. endpoint, what // ': wants_endpoint_solve')
        CHECK_TRUE(traits%continues_equilibrium .eqv. continued, what // ': continues_equilibrium')
        CHECK_EQUAL(traits%energy_scheme, energy, what // ': energy_scheme')
    end subroutine check_flags

    !> native_lu: PETSc's LU does not pivot, so every diagonal entry must be there and
    !> non-zero; the smallest is compared with the largest entry of its row. Nothing to check
    !> for a formulation that does not claim it.
    subroutine check_native_lu(rod, traits, what)
        class(rod_formulation_t), intent(inout) :: rod
        type(formulation_traits_t), intent(in) :: traits
        character(len=*), intent(in) :: what
        real(rk) :: smallest
        if (.not. traits%native_lu) return
        smallest = smallest_diagonal(rod)
        write(*, '(a,es10.3)') '  ' // what // ': smallest |diagonal| / row maximum = ', smallest
        ! PETSc's LU calls a pivot below 1e-12 zero (PCFactorSetZeroPivot's default).
        CHECK_TRUE(smallest > 1.0e-12_rk, what // ': a non-zero diagonal in every row (native_lu)')
    end subroutine check_native_lu

    !> min over rows of |J(i, i)| / max_j |J(i, j)| at a perturbed state (0 where J(i, i) is
    !> outside the pattern).
    real(rk) function smallest_diagonal(rod) result(smallest)
        class(rod_formulation_t), intent(inout) :: rod
        real(rk), allocatable :: values(:), x_n(:), y(:)
        integer, allocatable :: row_ptr(:), cols(:)
        integer :: row, k
        real(rk) :: diagonal
        call jacobian_at(rod, x_n, y, row_ptr, cols, values)
        smallest = huge(1.0_rk)
        do row = 1, rod%n_unknown()
            diagonal = 0.0_rk
            do k = row_ptr(row) + 1, row_ptr(row + 1)
                if (cols(k) == row - 1) diagonal = abs(values(k))
            end do
            smallest = min(smallest, diagonal / max(maxval(abs(values(row_ptr(row) + 1:row_ptr(row + 1)))), &
                tiny(1.0_rk)))
        end do
    end function smallest_diagonal

    !> |F(Y2) - F(Y1) - J(Y1) (Y2 - Y1)| / |F(Y2) - F(Y1)| (max norms), plus the change of J
    !> from Y1 to Y2 relative to its largest entry: zero for a step problem affine in Y.
    real(rk) function affine_defect(rod) result(defect)
        class(rod_formulation_t), intent(inout) :: rod
        real(rk), allocatable :: x_n(:), y1(:), y2(:), values1(:), values2(:), f1(:), f2(:), jd(:)
        real(rk), allocatable :: noise(:)
        integer, allocatable :: row_ptr(:), cols(:)
        integer :: n, row, k, status
        call jacobian_at(rod, x_n, y1, row_ptr, cols, values1)
        n = rod%n_unknown()
        allocate(noise(n), f1(n), f2(n), jd(n), values2(size(values1)))
        call random_number(noise)
        y2 = y1 + 0.05_rk * (noise - 0.5_rk)
        call rod%step_residual(fixture_t_n, fixture_h, x_n, y1, f1, status)
        call rod%step_residual(fixture_t_n, fixture_h, x_n, y2, f2, status)
        call rod%step_jacobian(fixture_t_n, fixture_h, x_n, y2, values2, status)
        jd = 0.0_rk
        do row = 1, n
            do k = row_ptr(row) + 1, row_ptr(row + 1)
                jd(row) = jd(row) + values1(k) * (y2(cols(k) + 1) - y1(cols(k) + 1))
            end do
        end do
        defect = maxval(abs(f2 - f1 - jd)) / maxval(abs(f2 - f1)) + &
            maxval(abs(values2 - values1)) / maxval(abs(values1))
    end function affine_defect

    !> The largest |row - column| of the pattern.
    integer function half_bandwidth(rod) result(width)
        class(rod_formulation_t), intent(in) :: rod
        integer, allocatable :: row_ptr(:), cols(:)
        integer :: row
        call rod%jacobian_pattern(row_ptr, cols)
        width = 0
        do row = 1, rod%n_unknown()
            if (row_ptr(row + 1) > row_ptr(row)) width = max(width, &
                maxval(abs(cols(row_ptr(row) + 1:row_ptr(row + 1)) - (row - 1))))
        end do
    end function half_bandwidth


    ! ---- Scenes --------------------------------------------------------------------------------

    !> Init `rod` on the fixture's cantilever (rs_test_formulation_fixture), quasistatic or
    !> dynamic; a scene that does not build stops the test.
    subroutine build(rod, name, n_elements, quasistatic, condense)
        class(rod_formulation_t), intent(inout) :: rod
        character(len=*), intent(in) :: name
        integer, intent(in) :: n_elements
        logical, intent(in) :: quasistatic
        logical, intent(in), optional :: condense
        logical :: ok
        call set_random_seed(20261126, n_elements + len_trim(name))
        call init_cantilever(rod, name, n_elements, ok, quasistatic, condense)
        if (.not. ok) error stop 'the cantilever of ' // name // ' does not build'
    end subroutine build

end module rs_test_formulation_traits

program test_formulation_traits
    use rs_test_assert, only: finish_tests
    use rs_test_formulation_traits, only: run_all_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_formulation_traits
