!> The record ledger (issue 22 item 3): what a run sums between two records, for every rod of
!> every formulation in one place. A formulation's accept_step gives the energy terms of a step
!> (rs_formulations_energy_sentinel's step_energy_t); the system layer books them here with the
!> solver's Newton statistics and the work of the couplings on each rod, writes the sums into
!> the rod's record and starts again (docs/user/output.md, "series/energy" and
!> "series/newton"):
!> - external_work: W, the work of the loads (and, in a system, of the coupling forces on the
!>   rod, so that each rod's balance closes by itself; docs/theory/bundles.md);
!> - actuator_work, dissipated: W_act and D (ph_director's actuators and Maxwell branches,
!>   se3_strand's damping);
!> - balance_error: sum of H_{n+1} - H_n - W - W_act + D over the steps (methods/
!>   ph_director_3d.md §5.3 item 1); for the rods of one object that share unknowns
!>   (formulation_traits_t%shared_balance) their sum, on the first rod;
!> - dt: the smallest step of the time (or load) grid since the record; newton_iterations:
!>   their sum (a linear step counts as one); newton_residual: the last step's residual.
!> A checkpoint holds these sums under their names (ledger_entry_names), so that a restart
!> continues them exactly (DESIGN.md §7).
module rs_system_ledger
    use rs_core_kinds, only: rk
    use rs_model_rod_history, only: rod_history_t
    use rs_formulations_energy_sentinel, only: step_energy_t
    implicit none
    private

    !> Number of checkpoint entries per rod.
    integer, parameter, public :: ledger_entries = 7

    !> One rod's sums since its last record.
    type :: rod_ledger_t
        real(rk) :: work = 0.0_rk
        real(rk) :: actuator_work = 0.0_rk
        real(rk) :: dissipated = 0.0_rk
        real(rk) :: balance = 0.0_rk
        real(rk) :: smallest_step = huge(1.0_rk)
        real(rk) :: last_residual = 0.0_rk
        integer :: iterations = 0
    end type rod_ledger_t

    type, public :: record_ledger_t
        type(rod_ledger_t), allocatable :: rods(:)
    contains
        procedure :: init => ledger_init
        !> Book an accepted step of the rods first..first + size(terms) - 1.
        procedure :: book_step => ledger_book_step
        !> Book work done on a rod by a coupling (external to the rod's own balance).
        procedure :: book_work => ledger_book_work
        !> Book dissipation of a coupling on a rod (friction).
        procedure :: book_dissipation => ledger_book_dissipation
        !> Write rod i's sums into its newest record and start again.
        procedure :: write_record => ledger_write_record
        !> The sums as checkpoint entries (ledger_entries per rod, named by
        !> ledger_entry_names) and back.
        procedure :: save => ledger_save
        procedure :: restore => ledger_restore
    end type record_ledger_t

    public :: ledger_entry_names

contains

    !> The names of a rod's checkpoint entries, in their order, separated by spaces.
    pure function ledger_entry_names() result(names)
        character(len=:), allocatable :: names
        names = 'external_work actuator_work dissipated balance_error dt newton_residual ' // &
            'newton_iterations'
    end function ledger_entry_names

    subroutine ledger_init(this, n_rods)
        class(record_ledger_t), intent(inout) :: this
        integer, intent(in) :: n_rods
        if (allocated(this%rods)) deallocate(this%rods)
        allocate(this%rods(n_rods))
    end subroutine ledger_init

    !> The terms of one accepted step of an object's rods, with the solver's Newton iterations
    !> and residual. `linear_step`: the step was one linear solve (counted as one iteration);
    !> `shared_balance`: the rods' balances are summed on the first (module header).
    subroutine ledger_book_step(this, first, terms, h, newton_iterations, residual_norm, &
            linear_step, shared_balance)
        class(record_ledger_t), intent(inout) :: this
        integer, intent(in) :: first
        type(step_energy_t), intent(in) :: terms(:)
        real(rk), intent(in) :: h
        integer, intent(in) :: newton_iterations
        real(rk), intent(in) :: residual_norm
        logical, intent(in) :: linear_step, shared_balance
        integer :: r, balance_rod
        do r = 1, size(terms)
            associate (rod => this%rods(first + r - 1), step => terms(r))
                rod%iterations = rod%iterations + merge(max(1, newton_iterations), &
                    newton_iterations, linear_step)
                rod%last_residual = merge(step%residual, residual_norm, step%residual >= 0.0_rk)
                if (step%grid_step) rod%smallest_step = min(rod%smallest_step, h)
                if (.not. step%reported) cycle
                rod%work = rod%work + step%work
                rod%actuator_work = rod%actuator_work + step%actuator_work
                rod%dissipated = rod%dissipated + step%dissipated
            end associate
            balance_rod = merge(first, first + r - 1, shared_balance)
            associate (rod => this%rods(balance_rod), step => terms(r))
                rod%balance = rod%balance + &
                    (step%after - step%before - step%work - step%actuator_work + step%dissipated)
            end associate
        end do
    end subroutine ledger_book_step

    subroutine ledger_book_work(this, i, work)
        class(record_ledger_t), intent(inout) :: this
        integer, intent(in) :: i
        real(rk), intent(in) :: work
        this%rods(i)%work = this%rods(i)%work + work
        this%rods(i)%balance = this%rods(i)%balance - work
    end subroutine ledger_book_work

    subroutine ledger_book_dissipation(this, i, dissipated)
        class(record_ledger_t), intent(inout) :: this
        integer, intent(in) :: i
        real(rk), intent(in) :: dissipated
        this%rods(i)%dissipated = this%rods(i)%dissipated + dissipated
        this%rods(i)%balance = this%rods(i)%balance + dissipated
    end subroutine ledger_book_dissipation

    subroutine ledger_write_record(this, i, history)
        class(record_ledger_t), intent(inout) :: this
        integer, intent(in) :: i
        type(rod_history_t), intent(inout) :: history
        integer :: r
        r = history%n_stored
        if (r > 0) then
            associate (rod => this%rods(i))
                history%external_work(r) = rod%work
                history%actuator_work(r) = rod%actuator_work
                history%dissipated(r) = rod%dissipated
                history%balance_error(r) = rod%balance
                history%newton_iterations(r) = rod%iterations
                history%newton_residual(r) = rod%last_residual
                history%dt(r) = merge(0.0_rk, rod%smallest_step, rod%smallest_step == huge(1.0_rk))
            end associate
        end if
        this%rods(i) = rod_ledger_t()
    end subroutine ledger_write_record

    !> values(ledger_entries, size(rods)) in the order of ledger_entry_names.
    subroutine ledger_save(this, values)
        class(record_ledger_t), intent(in) :: this
        real(rk), intent(out) :: values(:)
        integer :: i, at
        do i = 1, size(this%rods)
            at = ledger_entries * (i - 1)
            associate (rod => this%rods(i))
                values(at + 1:at + ledger_entries) = [rod%work, rod%actuator_work, rod%dissipated, &
                    rod%balance, rod%smallest_step, rod%last_residual, real(rod%iterations, rk)]
            end associate
        end do
    end subroutine ledger_save

    subroutine ledger_restore(this, values)
        class(record_ledger_t), intent(inout) :: this
        real(rk), intent(in) :: values(:)
        integer :: i, at
        do i = 1, size(this%rods)
            at = ledger_entries * (i - 1)
            this%rods(i) = rod_ledger_t(work=values(at + 1), actuator_work=values(at + 2), &
                dissipated=values(at + 3), balance=values(at + 4), smallest_step=values(at + 5), &
                last_residual=values(at + 6), iterations=nint(values(at + 7)))
        end do
    end subroutine ledger_restore

end module rs_system_ledger
