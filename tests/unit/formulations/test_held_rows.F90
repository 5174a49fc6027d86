#include "rs_assert.h"
!> Unit tests of rs_formulations_held_rows (issue 26 item 3, &bc release_time; docs/theory/
!> prestretched_starts.md, "Release"), on a 3 x 3 CSR pattern with plain numbers:
!> - while held, the row of a released coordinate is y - x_n(state) in the residual and the
!>   unit row in the Jacobian values (the other rows untouched);
!> - after the release both are left as the formulation made them;
!> - the switch: a step is held while its midpoint is before the release (a release on the
!>   grid frees the step that starts there), an equilibrium at load time t while t <= t_r;
!>   an unset release time (unset_real) holds always.
module rs_test_held_rows
    use rs_core_kinds, only: rk
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_model_scene, only: unset_real
    use rs_formulations_held_rows, only: held_rows_t
    implicit none
    private

    public :: run_all_tests

contains

    subroutine run_all_tests()
        call run_test('held_rows_replace_the_equations', test_rows)
        call run_test('the_release_time_switches', test_switch)
    end subroutine run_all_tests

    !> Rows 1..3 full (a dense 3 x 3 pattern); unknown 2 is state entry 5, released at t = 1.
    subroutine test_rows()
        type(held_rows_t) :: held
        real(rk) :: f(3), values(9), x_n(6), y(3)
        call held%init([2], [5], [1.0_rk], [1, 4, 7, 10], [1, 2, 3, 1, 2, 3, 1, 2, 3])
        x_n = [0.1_rk, 0.2_rk, 0.3_rk, 0.4_rk, 0.5_rk, 0.6_rk]
        y = [1.0_rk, 0.75_rk, 2.0_rk]
        f = [10.0_rk, 20.0_rk, 30.0_rk]
        values = [f(1), f(1), f(1), f(2), f(2), f(2), f(3), f(3), f(3)]
        call held%apply_residual(0.0_rk, 0.5_rk, .false., x_n, y, f)
        CHECK_CLOSE(f(2), 0.25_rk, 0.0_rk, 1e-15_rk, 'held: residual y - x_n(state)')
        CHECK_TRUE(f(1) == 10.0_rk .and. f(3) == 30.0_rk, 'held: other rows untouched')
        call held%apply_jacobian(0.0_rk, 0.5_rk, .false., values)
        CHECK_TRUE(all(values(4:6) == [0.0_rk, 1.0_rk, 0.0_rk]), 'held: the unit row')
        CHECK_TRUE(values(1) == 10.0_rk .and. all(values(7:9) == 30.0_rk), 'held: other rows of J untouched')
        f = [10.0_rk, 20.0_rk, 30.0_rk]
        values = 7.0_rk
        call held%apply_residual(1.0_rk, 0.5_rk, .false., x_n, y, f)
        call held%apply_jacobian(1.0_rk, 0.5_rk, .false., values)
        CHECK_TRUE(f(2) == 20.0_rk .and. all(values == 7.0_rk), 'released: the equations stay')
    end subroutine test_rows

    subroutine test_switch()
        type(held_rows_t) :: held
        call held%init([1, 2], [1, 2], [1.0_rk, unset_real], [1, 2, 3], [1, 2])
        CHECK_TRUE(held%is_held(1, 0.5_rk, 0.5_rk, .false.), 'the step ending at t_r is held')
        CHECK_TRUE(.not. held%is_held(1, 1.0_rk, 0.5_rk, .false.), 'the step starting at t_r is free')
        CHECK_TRUE(held%is_held(1, 0.8_rk, 0.3_rk, .false.), 'a step across t_r: its midpoint')
        CHECK_TRUE(.not. held%is_held(1, 0.8_rk, 0.5_rk, .false.), 'midpoint past t_r: free')
        CHECK_TRUE(held%is_held(1, 1.0_rk, 0.0_rk, .true.), 'an equilibrium at t = t_r is held')
        CHECK_TRUE(.not. held%is_held(1, 1.5_rk, 0.0_rk, .true.), 'an equilibrium after t_r is free')
        CHECK_TRUE(held%is_held(2, 1.0e6_rk, 1.0_rk, .false.), 'no release time: always held')
    end subroutine test_switch

end module rs_test_held_rows

program test_held_rows
    use rs_test_held_rows, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_held_rows
