!> The generalized-α method for first-order systems y' = F(t, y) of Jansen, Whiting and Hulbert
!> (2000), the scheme seed 002 runs its dynamics with (methods/se3_petrov_galerkin.md §7.3;
!> docs/theory/se3_pg.md, "Generalized-α"). One step from (y_n, y'_n) to (y_{n+1}, y'_{n+1}):
!>
!>     y_{n+1}      = y_n + h y'_n + h gamma (y'_{n+1} - y'_n),
!>     y'_{n+alpha_m} = F(t_n + alpha_f h, y_{n+alpha_f}),
!>
!> with the stage values y_{n+alpha_f} = y_n + alpha_f (y_{n+1} - y_n) and y'_{n+alpha_m} =
!> y'_n + alpha_m (y'_{n+1} - y'_n). The user's rho_inf in [0, 1], the spectral radius of the
!> step as h |lambda| -> infinity, sets
!>
!>     alpha_m = (3 - rho_inf) / (2 (1 + rho_inf)),  alpha_f = 1 / (1 + rho_inf),
!>     gamma = 1/2 + alpha_m - alpha_f,
!>
!> the choice of JWH 2000 that makes the step second-order accurate (gamma) and unconditionally
!> stable for linear problems (alpha_m >= alpha_f >= 1/2), with the high frequencies damped to
!> rho_inf per step (tests/unit/formulations/test_generalized_alpha measures both on y' = lambda y).
!> rho_inf = 1 is alpha_m = alpha_f = gamma = 1/2: the stage rate is then (y_{n+1} - y_n) / h
!> whatever y'_n, i.e. the implicit midpoint rule, which needs no history (`midpoint_scheme`).
!>
!> A formulation writes its step problem with the unknown y_{n+1} (or part of it): the
!> procedures below give the stage value, the stage rate and the end rate from the ends of the
!> step and the history y'_n, and back from a stage value to the end value, as linear maps.
!> Elemental (a component at a time, on arrays of any shape), so they make no temporaries.
module rs_formulations_generalized_alpha
    use rs_core_kinds, only: rk
    implicit none
    private

    public :: generalized_alpha, midpoint_scheme

    !> The coefficients of one generalized-α scheme; `history` is false for the midpoint rule,
    !> whose steps do not read y'_n (and whose state carries none).
    type, public :: generalized_alpha_t
        real(rk) :: alpha_m = 0.5_rk, alpha_f = 0.5_rk, gamma = 0.5_rk
        real(rk) :: rho_inf = 1.0_rk
        logical :: history = .false.
    contains
        !> y_{n+alpha_f} from the ends of the step.
        procedure :: stage_value
        !> y'_{n+alpha_m} from the ends of the step and y'_n.
        procedure :: stage_rate
        !> d y'_{n+alpha_m} / d y_{n+1} = alpha_m / (h gamma) (times the identity).
        procedure :: stage_rate_factor
        !> y'_{n+1} from the ends of the step and y'_n (the history of the next step).
        procedure :: end_rate
        !> y_{n+1} from y_n and the stage value y_{n+alpha_f}.
        procedure :: end_from_stage
    end type generalized_alpha_t

contains

    !> The scheme of spectral radius rho_inf at infinity (JWH 2000; methods §7.3).
    pure function generalized_alpha(rho_inf) result(scheme)
        real(rk), intent(in) :: rho_inf
        type(generalized_alpha_t) :: scheme
        scheme%rho_inf = rho_inf
        scheme%alpha_m = 0.5_rk * (3.0_rk - rho_inf) / (1.0_rk + rho_inf)
        scheme%alpha_f = 1.0_rk / (1.0_rk + rho_inf)
        scheme%gamma = 0.5_rk + scheme%alpha_m - scheme%alpha_f
        scheme%history = .true.
    end function generalized_alpha

    !> The implicit midpoint rule: rho_inf = 1 without the history it does not need.
    pure function midpoint_scheme() result(scheme)
        type(generalized_alpha_t) :: scheme
        scheme = generalized_alpha_t()
    end function midpoint_scheme

    elemental function stage_value(this, y_n, y_1) result(y_stage)
        class(generalized_alpha_t), intent(in) :: this
        real(rk), intent(in) :: y_n, y_1
        real(rk) :: y_stage
        y_stage = y_n + this%alpha_f * (y_1 - y_n)
    end function stage_value

    !> y'_{n+alpha_m} = y'_n + (alpha_m / gamma) ((y_{n+1} - y_n) / h - y'_n), from the update
    !> formula solved for y'_{n+1}; `rate_n` is not read by the midpoint rule (alpha_m = gamma).
    elemental function stage_rate(this, h, y_n, y_1, rate_n) result(rate)
        class(generalized_alpha_t), intent(in) :: this
        real(rk), intent(in) :: h, y_n, y_1, rate_n
        real(rk) :: rate
        if (this%history) then
            rate = this%stage_rate_factor(h) * (y_1 - y_n) + &
                (1.0_rk - this%alpha_m / this%gamma) * rate_n
        else
            rate = (y_1 - y_n) / h
        end if
    end function stage_rate

    elemental real(rk) function stage_rate_factor(this, h)
        class(generalized_alpha_t), intent(in) :: this
        real(rk), intent(in) :: h
        stage_rate_factor = this%alpha_m / (h * this%gamma)
    end function stage_rate_factor

    !> y'_{n+1} = y'_n + ((y_{n+1} - y_n) / h - y'_n) / gamma.
    elemental function end_rate(this, h, y_n, y_1, rate_n) result(rate)
        class(generalized_alpha_t), intent(in) :: this
        real(rk), intent(in) :: h, y_n, y_1, rate_n
        real(rk) :: rate
        rate = (y_1 - y_n) / (h * this%gamma) + (1.0_rk - 1.0_rk / this%gamma) * rate_n
    end function end_rate

    !> y_{n+1} = y_n + (y_{n+alpha_f} - y_n) / alpha_f.
    elemental function end_from_stage(this, y_n, y_stage) result(y_1)
        class(generalized_alpha_t), intent(in) :: this
        real(rk), intent(in) :: y_n, y_stage
        real(rk) :: y_1
        y_1 = y_n + (y_stage - y_n) / this%alpha_f
    end function end_from_stage

end module rs_formulations_generalized_alpha
