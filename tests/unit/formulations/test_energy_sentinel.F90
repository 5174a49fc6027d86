#include "rs_assert.h"
!> Unit tests of rs_formulations_energy_sentinel (issue 21 item 12, docs/stability.md "The
!> energy sentinel"), on plain numbers:
!> - energy-consistent: a step whose balance error is within 1e-4 of its energy scale passes,
!>   one just beyond trips it, with that step's time, error and allowance; a loss trips it as a
!>   gain does; a NaN balance trips it;
!> - dissipative: a run that creates energy step by step but stays below 10 times the energy
!>   that entered passes; one that goes on doubling its energy with no work trips it at the
!>   step the created energy passes 10 times the initial energy; a step that dissipates is never
!>   a trip;
!> - unchecked schemes and unreported steps never trip; once tripped, later steps change
!>   nothing; the messages name t, the energy and the hint.
module rs_test_energy_sentinel
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use rs_core_kinds, only: rk
    use rs_test_assert, only: run_test, assert_true, assert_close
    use rs_formulations_energy_sentinel, only: energy_sentinel_t, step_energy_t, &
        energy_consistent, energy_dissipative, energy_unchecked, consistent_allowance, &
        dissipative_allowance
    implicit none
    private

    public :: run_all_tests

contains

    subroutine run_all_tests()
        call run_test('consistent', test_consistent)
        call run_test('dissipative', test_dissipative)
        call run_test('unchecked', test_unchecked)
    end subroutine run_all_tests

    subroutine test_consistent()
        type(energy_sentinel_t) :: sentinel
        type(step_energy_t) :: step
        real(rk) :: nan
        ! Scale 2 + 1 = 3: allowance 3e-4.
        step = step_energy_t(reported=.true., before=1.0_rk, after=2.0_rk, work=1.0_rk)
        step%after = 2.0_rk + 0.99_rk * consistent_allowance * 3.0_rk
        call sentinel%check(energy_consistent, step, 1.0_rk)
        CHECK_TRUE(.not. sentinel%tripped, 'a balance error within the allowance passes')
        step%after = 2.0_rk + 1.01_rk * consistent_allowance * 3.0_rk
        call sentinel%check(energy_consistent, step, 2.0_rk)
        CHECK_TRUE(sentinel%tripped, 'a balance error beyond the allowance trips')
        CHECK_CLOSE(sentinel%t, 2.0_rk, 0.0_rk, 0.0_rk, 'the time of the step')
        CHECK_CLOSE(sentinel%gain, 3.03e-4_rk, 0.0_rk, 1e-6_rk, 'the balance error')
        CHECK_TRUE(index(sentinel%message(), 'energy sentinel at t = 2') > 0, 'message: t')
        CHECK_TRUE(index(sentinel%message(), 'smaller dt') > 0, 'message: the hint')
        ! Once tripped, a later step changes nothing.
        call sentinel%check(energy_consistent, step, 3.0_rk)
        CHECK_CLOSE(sentinel%t, 2.0_rk, 0.0_rk, 0.0_rk, 'the first trip is kept')
        sentinel = energy_sentinel_t()
        step%after = 2.0_rk - 1.01_rk * consistent_allowance * 3.0_rk
        call sentinel%check(energy_consistent, step, 1.0_rk)
        CHECK_TRUE(sentinel%tripped, 'a loss beyond the allowance trips as well')
        sentinel = energy_sentinel_t()
        nan = ieee_value(nan, ieee_quiet_nan)
        step%after = nan
        call sentinel%check(energy_consistent, step, 1.0_rk)
        CHECK_TRUE(sentinel%tripped, 'a NaN balance trips')
    end subroutine test_consistent

    subroutine test_dissipative()
        type(energy_sentinel_t) :: sentinel
        type(step_energy_t) :: step
        real(rk) :: h
        integer :: n
        ! Creates 0.5 J per step against 1 J of work per step: created / entered stays below 1.
        do n = 1, 1000
            step = step_energy_t(reported=.true., before=real(n, rk), after=real(n, rk) + 1.5_rk, &
                work=1.0_rk)
            call sentinel%check(energy_dissipative, step, real(n, rk))
        end do
        CHECK_TRUE(.not. sentinel%tripped, 'energy created below the energy that entered passes')
        ! Dissipating steps never trip.
        sentinel = energy_sentinel_t()
        do n = 1, 100
            step = step_energy_t(reported=.true., before=1.0_rk, after=0.5_rk)
            call sentinel%check(energy_dissipative, step, real(n, rk))
        end do
        CHECK_TRUE(.not. sentinel%tripped, 'a dissipating scheme passes')
        ! A blow-up: H doubles every step from 1 J, no work. Created after n steps: 2^n - 1,
        ! which passes 10 (10 times the initial 1 J) at n = 4 (15 J).
        sentinel = energy_sentinel_t()
        h = 1.0_rk
        do n = 1, 10
            step = step_energy_t(reported=.true., before=h, after=2.0_rk * h)
            call sentinel%check(energy_dissipative, step, real(n, rk))
            h = 2.0_rk * h
        end do
        CHECK_TRUE(sentinel%tripped, 'a blow-up trips')
        CHECK_CLOSE(sentinel%t, 4.0_rk, 0.0_rk, 0.0_rk, 'at the step it passes the allowance')
        CHECK_CLOSE(sentinel%gain, 15.0_rk, 0.0_rk, 1e-14_rk, 'the energy created')
        CHECK_CLOSE(sentinel%allowance, dissipative_allowance, 0.0_rk, 1e-14_rk, 'allowance')
        CHECK_TRUE(index(sentinel%message(), 'created 1.5') > 0, 'message: the energy')
    end subroutine test_dissipative

    subroutine test_unchecked()
        type(energy_sentinel_t) :: sentinel
        type(step_energy_t) :: step
        step = step_energy_t(reported=.true., before=1.0_rk, after=1e10_rk)
        call sentinel%check(energy_unchecked, step, 1.0_rk)
        CHECK_TRUE(.not. sentinel%tripped, 'an unchecked scheme never trips')
        step%reported = .false.
        call sentinel%check(energy_consistent, step, 1.0_rk)
        call sentinel%check(energy_dissipative, step, 1.0_rk)
        CHECK_TRUE(.not. sentinel%tripped, 'an unreported step never trips')
    end subroutine test_unchecked

end module rs_test_energy_sentinel

program test_energy_sentinel
    use rs_test_energy_sentinel, only: run_all_tests
    use rs_test_assert, only: finish_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_energy_sentinel
