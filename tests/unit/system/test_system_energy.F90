#include "rs_assert.h"
!> The system layer's energy book-keeping of couplings (issue 22; rs_system_rod_system
!> accept_step, record): for two crossing ph_director rods in contact, with no loads, a step
!> from X_n to any X_{n+1} (it need not solve the step) books the contact's work on the rods
!> as their external work, and that work is minus the change of the contact energy, exactly
!> (the contact force is a discrete gradient, rs_contact_element). The contact energies come
!> from the records at X_n and X_{n+1} (series contact_energy, the rods' halves summed), the
!> work from the step's energy terms (step_energy, what the energy sentinel checks) and from
!> the ledger's record (external_work): three independent paths. With joints (the chain of
!> the same rods joined rigidly, no contact) the ties do no work on the pair of rods together:
!> -lambda (g(z_1) - g(z_n)) with g(z_1) = g(z_n) = 0 for states that hold the joint.
module rs_test_system_energy
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, error_list_t
    use rs_test_assert, only: run_test, assert_true, assert_equal
    use rs_test_random, only: set_random_seed
    use rs_model_scene, only: scene_t
    use rs_model_rod_history, only: rod_history_t
    use rs_io_input_file, only: parse_scene
    use rs_system_rod_system, only: rod_system_t
    implicit none
    private

    public :: run_all_tests

    character(len=*), parameter :: nl = new_line('a')

contains

    subroutine run_all_tests()
        call run_test('contact_work_is_energy_change', test_contact_work)
    end subroutine run_all_tests

    !> Two ph_director rods crossing 0.09 apart with contact radii 0.05 (in contact), free of
    !> supports and loads; the step moves the upper one down by 0.004 and both by random
    !> 1e-4, so the contact energy changes by a large fraction of itself.
    subroutine test_contact_work()
        type(scene_t) :: scene
        type(error_list_t) :: errors
        type(error_t), allocatable :: err
        type(rod_system_t) :: system
        type(rod_history_t) :: histories(2)
        real(rk), allocatable :: x_n(:), x_1(:), noise(:)
        real(rk) :: energy_n, energy_1, work_terms, work_ledger, scale
        integer :: r, k
        logical :: ok
        character(len=:), allocatable :: text
        text = '&time t_end = 1, dt = 0.01 /' // nl // &
            "&rod name = 'a', n_elements = 6, degree = 2, length = 1, start = -0.5, 0, 0.09," // &
            ' direction = 1, 0, 0, EA = 1e4, GA1 = 8e3, GA2 = 6e3, EI1 = 50, EI2 = 40, GJ = 30,' // &
            ' rhoA = 1, rhoI1 = 0.01, rhoI2 = 0.02, contact_radius = 0.05 /' // nl // &
            "&rod name = 'b', n_elements = 6, degree = 2, length = 1, start = 0, -0.5, 0," // &
            ' direction = 0, 1, 0, EA = 1e4, GA1 = 8e3, GA2 = 6e3, EI1 = 50, EI2 = 40, GJ = 30,' // &
            ' rhoA = 1, rhoI1 = 0.01, rhoI2 = 0.02, contact_radius = 0.05 /' // nl // &
            '&contact stiffness = 1e7, margin = 0.05 /' // nl
        call parse_scene(text, 'energy.nml', scene, errors)
        CHECK_EQUAL(errors%count, 0, 'the scene parses: ' // errors%joined())
        if (errors%count > 0) return
        call system%init(scene, [1, 2], err)
        ok = .not. allocated(err)
        CHECK_TRUE(ok, 'system init')
        if (.not. ok) return
        call set_random_seed(20261126, 1)
        allocate(x_n(system%n_state()), x_1(system%n_state()), noise(system%n_state()))
        call system%initial_state(x_n)
        x_1 = x_n
        ! Move rod a's positions (the first three coordinates of every node) down by 0.004.
        do k = 1, system%layout%members(1)%nodes%n_nodes
            associate (i => system%layout%members(1)%nodes%state(3, k))
                if (i > 0) x_1(system%layout%members(1)%state_offset + i) = &
                    x_1(system%layout%members(1)%state_offset + i) - 0.004_rk
            end associate
        end do
        call system%init_history(histories, 10)
        call system%prepare_step(0.0_rk, 0.01_rk, x_n, ok)
        call system%record(histories, 0.0_rk, x_n)
        energy_n = histories(1)%contact_energy(1) + histories(2)%contact_energy(1)
        call system%accept_step(0.0_rk, 0.01_rk, x_n, x_1, 2, 1.0e-12_rk)
        work_terms = system%step_energy%work
        call system%record(histories, 0.01_rk, x_1)
        energy_1 = histories(1)%contact_energy(2) + histories(2)%contact_energy(2)
        work_ledger = sum([(histories(r)%external_work(2), r = 1, 2)])
        scale = max(abs(energy_n), abs(energy_1))
        write(*, '(a,3es12.4)') '  contact energy at X_n, X_1 and the work booked: ', energy_n, &
            energy_1, work_terms
        write(*, '(a,2es10.2)') '  relative: |W + dE|, |W_ledger - W|: ', &
            abs(work_terms + (energy_1 - energy_n)) / scale, abs(work_ledger - work_terms) / scale
        ok = energy_n > 0.0_rk .and. abs(energy_1 - energy_n) > 0.1_rk * scale
        CHECK_TRUE(ok, 'the rods touch and the step changes the contact energy by > 10 %')
        ! Round-off of the sums over the contact point pairs and nodes: measured 6.5e-16 of the
        ! energy; bound 5e-14 (77 times).
        ok = abs(work_terms + (energy_1 - energy_n)) <= 5.0e-14_rk * scale
        CHECK_TRUE(ok, 'the contact work of the step is minus the change of the contact energy')
        ! The same two rod works, summed in the ledger and in the step's terms: measured 0.
        ok = abs(work_ledger - work_terms) <= 1.0e-15_rk * scale
        CHECK_TRUE(ok, 'the ledger books the same work on the rods as the sentinel sees')
    end subroutine test_contact_work

end module rs_test_system_energy

program test_system_energy
    use rs_test_assert, only: finish_tests
    use rs_test_system_energy, only: run_all_tests
    implicit none
    call run_all_tests()
    call finish_tests()
end program test_system_energy
