!> The energy sentinel of a run (issue 21 item 12, docs/stability.md "The energy sentinel"): a
!> rod whose scheme creates energy beyond what the scheme allows is stopped with status
!> `failed`, instead of running on to a blown-up state reported as completed.
!>
!> Each formulation books the energy terms of every accepted (sub)step in its accept_step
!> (step_energy_t: H_n, H_{n+1}, the work W of the loads and the energy D dissipated) and says
!> which kind of scheme it is (energy_scheme); the balance error is b = H_{n+1} - H_n - W + D,
!> positive when the step created energy. The test depends only on the kind:
!> - energy-consistent schemes (the EM midpoint rules of ph_director and ph_planar) make b zero
!>   up to the Newton tolerance and round-off: a step fails when |b| exceeds
!>   consistent_allowance times the step's energy scale max(|H_n|, |H_{n+1}|) + |W| + |D|;
!> - the semi-implicit se3_strand scheme is first order and not dissipative step by step (its
!>   frozen ad coefficients exchange O(dt) energy of either sign, docs/theory/se3_strand.md),
!>   so a single step may create some energy; what it cannot do is create energy on the scale of
!>   all the energy the rod ever held: the rod fails when the energy created since the start,
!>   sum b, exceeds dissipative_allowance times the energy that entered it, |H_0| + sum (|W| +
!>   |D|);
!>   se3_pg's generalized-alpha scheme (docs/theory/se3_pg.md) is checked this way too: it is
!>   stable and damps, so a blown-up run is all the test may catch;
!> - other schemes (se3_pg's midpoint rule, which is not energy-consistent for that element,
!>   docs/theory/se3_pg.md) are not checked.
!> A coupled system is checked as its rods' scheme, on the sum of the rods' terms with the
!> couplings' work on each rod booked as external work (rs_system_rod_system).
!> No PETSc, no MPI: unit-tested on plain numbers (tests/unit/formulations/test_energy_sentinel).
module rs_formulations_energy_sentinel
    use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
    use rs_core_kinds, only: rk
    use rs_core_strings, only: str_significant
    implicit none
    private

    !> The kinds of scheme (rod_formulation_t%energy_scheme).
    integer, parameter, public :: energy_unchecked = 0, energy_consistent = 1, &
        energy_dissipative = 2
    !> |b| allowed per step of an energy-consistent scheme, relative to the step's energy scale:
    !> over the regression scenes the largest measured is 1.1e-7 (ph_planar's four-bar, Newton's
    !> default newton_atol = 1e-10); round-off alone is about 1e-15.
    real(rk), parameter, public :: consistent_allowance = 1.0e-4_rk
    !> Energy the semi-implicit scheme may create, relative to the energy that entered the rod:
    !> over the regression scenes the largest measured is 1.9 (the paper's internal law at
    !> eta_in = 1e4, which the balance books as negative dissipation), 0.15 on the 600 N bend
    !> and 0.02 on the driven spin-up; a blown-up run creates 1e5 and more.
    real(rk), parameter, public :: dissipative_allowance = 10.0_rk

    !> The terms of one accepted (sub)step of one rod, as its formulation's accept_step gives
    !> them (rs_formulations_formulation): the energy terms for the sentinel and the record
    !> ledger (rs_system_ledger), and how the step counts in the ledger's statistics.
    type, public :: step_energy_t
        !> False: the step has no energy terms (an endpoint equilibrium, statics of a
        !> formulation that books none).
        logical :: reported = .false.
        !> H_n and H_{n+1} (kinetic plus stored energy), the work of the loads and of the
        !> actuators, and the energy dissipated over the step.
        real(rk) :: before = 0.0_rk, after = 0.0_rk, work = 0.0_rk, actuator_work = 0.0_rk
        real(rk) :: dissipated = 0.0_rk
        !> The step is one of the time (or load) grid, so its h counts for the smallest step
        !> of the record; false: an endpoint equilibrium solve (only its Newton iterations
        !> count).
        logical :: grid_step = .true.
        !> The step's achieved residual when the formulation measures it itself (a linear step,
        !> whose solver reports none); negative: the Newton residual the solver reports.
        real(rk) :: residual = -1.0_rk
    end type step_energy_t

    !> One rod's (system's) sentinel: the sums of the dissipative test and what tripped it.
    type, public :: energy_sentinel_t
        logical :: started = .false.
        !> sum b and |H_0| + sum (|W| + |D|) since the start (or the restart).
        real(rk) :: created = 0.0_rk, entered = 0.0_rk
        logical :: tripped = .false.
        integer :: kind = energy_unchecked
        !> When it tripped: the end of the step, the energy created (|b| for a consistent
        !> scheme) and the allowance it exceeded.
        real(rk) :: t = 0.0_rk, gain = 0.0_rk, allowance = 0.0_rk
    contains
        !> Add the step that ended at time t; trips the sentinel if the scheme's allowance is
        !> exceeded (once: later steps change nothing).
        procedure :: check => sentinel_check
        !> Why it tripped, for the rod's error message.
        procedure :: message => sentinel_message
    end type energy_sentinel_t

contains

    subroutine sentinel_check(this, kind, step, t)
        class(energy_sentinel_t), intent(inout) :: this
        integer, intent(in) :: kind
        type(step_energy_t), intent(in) :: step
        real(rk), intent(in) :: t
        real(rk) :: balance, scale
        if (this%tripped .or. kind == energy_unchecked .or. .not. step%reported) return
        balance = step%after - step%before - (step%work + step%actuator_work) + step%dissipated
        if (ieee_is_nan(balance)) then
            call trip(balance, 0.0_rk)
            return
        end if
        select case (kind)
        case (energy_consistent)
            scale = max(abs(step%before), abs(step%after)) + abs(step%work + step%actuator_work) + &
                abs(step%dissipated)
            if (abs(balance) > consistent_allowance * scale) &
                call trip(balance, consistent_allowance * scale)
        case (energy_dissipative)
            if (.not. this%started) this%entered = abs(step%before)
            this%started = .true.
            this%created = this%created + balance
            this%entered = this%entered + abs(step%work + step%actuator_work) + abs(step%dissipated)
            if (this%created > dissipative_allowance * this%entered) &
                call trip(this%created, dissipative_allowance * this%entered)
        end select
    contains
        subroutine trip(gain, allowance)
            real(rk), intent(in) :: gain, allowance
            this%tripped = .true.
            this%kind = kind
            this%t = t
            this%gain = gain
            this%allowance = allowance
        end subroutine trip
    end subroutine sentinel_check

    function sentinel_message(this) result(text)
        class(energy_sentinel_t), intent(in) :: this
        character(len=:), allocatable :: text
        if (this%kind == energy_consistent) then
            text = 'energy sentinel at t = ' // str_significant(this%t, 6) // ': the step''s ' // &
                'energy balance error H_n+1 - H_n - W + D is ' // str_significant(this%gain, 3) // &
                ' J (energy created if positive, lost if negative), beyond the allowance +-' // &
                str_significant(this%allowance, 3) // ' J (1e-4 of the step''s energy) of ' // &
                'this energy-consistent scheme; try a smaller dt (or a smaller newton_atol) ' // &
                '(docs/stability.md, "The energy sentinel")'
        else
            text = 'energy sentinel at t = ' // str_significant(this%t, 6) // ': the ' // &
                'scheme has created ' // str_significant(this%gain, 3) // ' J of energy ' // &
                'since the start, beyond the allowance ' // str_significant(this%allowance, 3) // &
                ' J (10 times the energy that entered the rod: its initial energy, the ' // &
                'work of the loads and the dissipation); the semi-implicit step is unstable ' // &
                'here: try a smaller dt, or apply the load gradually ' // &
                '(docs/stability.md, "The energy sentinel")'
        end if
    end function sentinel_message

end module rs_formulations_energy_sentinel
