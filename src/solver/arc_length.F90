#include "rs_macros.h"
!> Arc-length continuation of the statics (issue 27 item 3, docs/theory/continuation.md): the
!> equilibrium path R(Y; lambda) = 0 of a system traced with the load time lambda as an unknown,
!> through limit points where load stepping stops, written once for every formulation with a
!> static problem (rod_system_t%set_load_problem: ph_director's and the planar schemes'
!> endpoint statics, se3_pg's equilibrium steps).
!>
!> The path is measured in a scaled norm (rod_system_t%path_weights, with mu = lambda / t_end):
!> ds^2 = mean over the nodes of (|dr|^2 / L^2 + |dtheta|^2) + dmu^2. Each step is Riks's
!> (Riks 1979; Crisfield, Non-linear finite element analysis of solids and structures, vol. 1,
!> §9.3): the predictor goes a length ds along the unit tangent t = (dY/dmu, 1) / |.| at the
!> last point, oriented along the last secant so that the path does not turn back at a limit
!> point; the corrector is Newton on R = 0 in the hyperplane normal to t through the
!> predictor, t . (Y - Y0, mu - mu0) = ds. The constraint is linear, so every Newton update keeps
!> it exactly, and the bordered system [J R_mu; t_Y^T w, t_mu] is solved by block elimination
!> with two solves of one factorization of J (the stepper's own linear solver: the chain LU for
!> one rod, DESIGN.md §3): J a = -R, J b = -R_mu, dmu = -(t_Y . w a) / (t_Y . w b + t_mu), dY = a
!> + dmu b. J stays regular at a limit point (only the bordered matrix is needed there); it is
!> singular only at a bifurcation, which a perfect structure meets: the critical eigenvalue of
!> the stiffness is followed along the path by inverse iteration on the same factorization,
!> a bifurcation is where it changes sign while the load keeps its direction, and with
!> branch_switch the path leaves the first one along its mode, the branch's tangent at a
!> simple symmetric bifurcation (Keller 1977, "Numerical solution of bifurcation and nonlinear
!> eigenvalue problems"; docs/theory/continuation.md, "Bifurcations").
!> R_mu = dR/dmu is a difference of R in the load time (exact to round-off for loads linear in
!> their time functions: the residual is then affine in the loads).
!>
!> A step whose Newton fails, whose corrector ends farther from its predictor than the step's
!> length (it jumped to another part of the path), or that turns a section by more than
!> max_rotation, is halved; the next step's length follows the iterations, ds sqrt(
!> target_iterations / iterations) within [ds / 2, 2 ds] and [arc_length_min, arc_length_max].
!> The tangent at a new point reuses the last corrector iteration's factorization when the
!> point's coordinates are the corrector's (a quarter fewer factorizations).
module rs_solver_arc_length
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: str, str_significant
    use rs_formulations_formulation, only: state_measures_t, state_valid
    use rs_system_rod_system, only: rod_system_t
    use rs_solver_rod_stepper, only: rod_stepper_t
    implicit none
    private

    !> The continuation's settings (&time continuation = 'arc_length' and its variables).
    type, public :: arc_length_settings_t
        !> First arc length, and its bounds, in the scaled norm of the module header.
        real(rk) :: arc_length = 0.05_rk
        real(rk) :: arc_length_max = 0.2_rk
        real(rk) :: arc_length_min = 1.0e-8_rk
        !> The load time's scale t_end: mu = lambda / t_end in the path length.
        real(rk) :: load_scale = 1.0_rk
        !> Newton's stopping rule and iterations per attempt (&solver).
        real(rk) :: newton_atol = 1.0e-10_rk
        integer :: max_newton = 25
        !> The iterations a step of the right length takes.
        integer :: target_iterations = 4
        !> The largest turn (radians) of a section in one step: a longer step may have jumped
        !> to another branch, as in rod_run's continue_equilibrium.
        real(rk) :: max_rotation = 0.5_rk
        !> The first step's direction in the load: +1 (the load grows) or -1.
        real(rk) :: direction = 1.0_rk
        !> At the first bifurcation the path crosses, leave the path for the branch that
        !> bifurcates there (&time branch_switch); false: bifurcations are reported only.
        logical :: branch_switch = .false.
    end type arc_length_settings_t

    !> A path being traced: the current point's load time and the next step's length, the last
    !> secant (the tangent's orientation), and the work arrays (allocated once: no allocation in
    !> the path's loop).
    type, public :: arc_length_path_t
        type(arc_length_settings_t) :: settings
        !> Load time lambda of the current point and the next step's arc length.
        real(rk) :: load = 0.0_rk
        real(rk) :: step = 0.0_rk
        !> The last step's Newton iterations (Jacobians factored) and its halvings; the
        !> factorizations of the whole path (tangents included).
        integer :: iterations = 0
        integer :: cutbacks = 0
        integer :: factorizations = 0
        !> Largest residual |R|_inf of the last point.
        real(rk) :: residual = 0.0_rk
        !> The stepper's factorization is J at the last corrector iterate of the accepted step.
        logical :: fresh = .false.
        !> The last secant (dY, dmu) / ds, in the scaled norm a unit vector.
        logical :: has_secant = .false.
        real(rk), allocatable :: secant(:)
        real(rk) :: secant_load = 0.0_rk
        real(rk), allocatable :: weights(:), tangent(:), y_start(:), y(:), f(:), f_plus(:), &
            a(:), b(:), values(:), x_new(:)
        !> Bifurcations (track_critical_mode): the critical eigenvalue at the current point and
        !> its (unit in the path's norm) mode, by inverse iteration carried along the path,
        !> and those of the point before; the current point is `tested`.
        real(rk) :: critical = 0.0_rk, critical_before = 0.0_rk
        !> The load time (over t_end) of the point before.
        real(rk) :: mu_before = 0.0_rk
        real(rk), allocatable :: mode(:), mode_before(:)
        !> The row of the force conjugate to each unknown (rod_system_t%force_rows).
        integer, allocatable :: force_rows(:)
        logical :: has_critical = .false., tested = .false.
        !> The load component of the tangent at the point before (a limit point turns it).
        real(rk) :: tangent_load_before = 0.0_rk
        !> Bifurcations crossed, the load time of the last one, and the switch to its branch:
        !> pending (the next step leaves along the mode) and done.
        integer :: bifurcations = 0
        real(rk) :: bifurcation_load = 0.0_rk
        logical :: switch_pending = .false., switched = .false.
        !> What the last step found (a bifurcation, the switch), for the run's log; empty:
        !> nothing.
        character(len=:), allocatable :: event
    contains
        procedure :: init => path_init
        !> One step along the path from the state x at the load time `load`: x and load become
        !> the next point's; on failure (halved below arc_length_min) err says why and x is kept.
        procedure :: advance => path_advance
    end type arc_length_path_t

contains

    !> The path from the state x in equilibrium at the load time `load`: the system's step
    !> problem becomes the statics for the whole path (set_load_problem once; every
    !> evaluation then only sets its load time).
    subroutine path_init(this, system, settings, n_values, load, x)
        class(arc_length_path_t), intent(inout) :: this
        type(rod_system_t), intent(inout) :: system
        type(arc_length_settings_t), intent(in) :: settings
        integer, intent(in) :: n_values
        real(rk), intent(in) :: load, x(:)
        integer :: n, i
        this%settings = settings
        this%load = load
        this%step = settings%arc_length
        this%has_secant = .false.
        this%fresh = .false.
        this%factorizations = 0
        n = system%n_unknown()
        if (allocated(this%weights)) deallocate(this%weights, this%tangent, this%y_start, this%y, &
            this%f, this%f_plus, this%a, this%b, this%values, this%secant, this%x_new, &
            this%mode, this%mode_before, this%force_rows)
        allocate(this%weights(n), this%tangent(n), this%y_start(n), this%y(n), this%f(n), &
            this%f_plus(n), this%a(n), this%b(n), this%secant(n), this%mode(n), &
            this%mode_before(n), this%force_rows(n))
        allocate(this%values(n_values), this%x_new(system%n_state()))
        ! Inverse iteration's start: every component present, none favoured (a fixed sequence,
        ! so that runs repeat).
        this%mode = [(sin(1.0_rk + 0.7_rk * real(i, rk)), i = 1, n)]
        this%has_critical = .false.
        this%tested = .false.
        this%bifurcations = 0
        this%switch_pending = .false.
        this%switched = .false.
        this%event = ''
        call system%path_weights(this%weights)
        call system%force_rows(this%force_rows)
        this%mode = this%mode / sqrt(weighted(this, this%mode, this%mode))
        call system%set_load_problem(load, base=x)
    end subroutine path_init

    subroutine path_advance(this, system, stepper, x, err)
        class(arc_length_path_t), intent(inout) :: this
        type(rod_system_t), intent(inout) :: system
        type(rod_stepper_t), intent(inout) :: stepper
        real(rk), intent(inout) :: x(:)
        type(error_t), allocatable, intent(out) :: err
        character(len=:), allocatable :: why
        logical :: converged
        real(rk) :: t_n, h
        this%cutbacks = 0
        do
            call try_step(this, system, stepper, x, converged, why, err)
            RS_RETURN_IF_ERROR(err)
            if (converged) exit
            if (0.5_rk * this%step < this%settings%arc_length_min) then
                RS_SET_ERROR(err, 'arc_length%advance', 'no point of the path within an arc length of ' // str_significant(this%step, 3) // ' from the load time ' // str_significant(this%load, 8) // ' (arc_length_min = ' // str_significant(this%settings%arc_length_min, 3) // '): ' // why)
                return
            end if
            this%step = 0.5_rk * this%step
            this%cutbacks = this%cutbacks + 1
        end do
        ! Booked as a step of the statics at the new point's load (the ledger's Newton counts).
        call system%load_step(this%load, t_n, h)
        call system%accept_step(t_n, h, x, this%x_new, this%iterations, this%residual)
        x = this%x_new
        this%tested = .false.
        ! The next step's length from this one's iterations (halved steps do not grow at once).
        if (this%cutbacks == 0) this%step = this%step * min(2.0_rk, max(0.5_rk, &
            sqrt(real(this%settings%target_iterations, rk) / max(1, this%iterations))))
        this%step = min(this%settings%arc_length_max, max(this%settings%arc_length_min, this%step))
    end subroutine path_advance

    !> One attempt at a step of length this%step; `why` says what failed when not converged.
    subroutine try_step(this, system, stepper, x, converged, why, err)
        type(arc_length_path_t), intent(inout) :: this
        type(rod_system_t), intent(inout) :: system
        type(rod_stepper_t), intent(inout) :: stepper
        real(rk), intent(in) :: x(:)
        logical, intent(out) :: converged
        character(len=:), allocatable, intent(out) :: why
        type(error_t), allocatable, intent(out) :: err
        real(rk) :: mu_start, mu, tangent_mu, norm, t_n, h, dmu, turn
        type(state_measures_t) :: measures
        integer :: iteration
        logical :: ok
        converged = .false.
        why = ''
        mu_start = this%load / this%settings%load_scale
        call system%set_load_problem(this%load)
        call system%load_step(this%load, t_n, h)
        call system%predictor(t_n, h, x, this%y_start)

        ! The tangent at the start point: J dY/dmu = -R_mu, t = (dY/dmu, 1) / |.|. J is that of
        ! the last corrector iteration where the last step ended with one and the start point
        ! has the same coordinates (no rotation vector complemented): the tangent only orients
        ! the predictor and its hyperplane, so it need not be exact (saves one factorization
        ! per step, about a quarter of them).
        if (.not. (this%fresh .and. all(this%y_start == this%y))) then
            call factor(this, system, stepper, x, this%y_start, mu_start, ok, why, err)
            RS_RETURN_IF_ERROR(err)
            if (.not. ok) return
        end if
        this%fresh = .false.
        call residual(this, system, x, this%y_start, mu_start, this%f, ok)
        if (ok) call load_derivative(this, system, x, this%y_start, mu_start, ok)
        if (.not. ok) then
            why = 'the residual is invalid at the start point'
            return
        end if
        call solve(stepper, this%f, this%b, ok, err)
        RS_RETURN_IF_ERROR(err)
        if (.not. ok) then
            why = 'the linear solve of the tangent failed'
            return
        end if
        this%b = -this%b
        norm = sqrt(weighted(this, this%b, this%b) + 1.0_rk)
        this%tangent = this%b / norm
        tangent_mu = 1.0_rk / norm
        ! Along the last secant (past a limit point the load turns back); the first step goes
        ! the way of `direction` in the load.
        if (this%has_secant) then
            if (weighted(this, this%tangent, this%secant) + tangent_mu * this%secant_load < &
                    0.0_rk) then
                this%tangent = -this%tangent
                tangent_mu = -tangent_mu
            end if
        else if (this%settings%direction < 0.0_rk) then
            this%tangent = -this%tangent
            tangent_mu = -tangent_mu
        end if

        ! Once per point: the critical eigenvalue there, and whether the last step crossed a
        ! bifurcation (with branch_switch, the first one is left along its mode).
        if (.not. this%tested) then
            call track_critical_mode(this, stepper, ok, err)
            RS_RETURN_IF_ERROR(err)
            if (.not. ok) then
                why = 'a linear solve of the critical mode failed'
                return
            end if
            this%tested = .true.
            call check_bifurcation(this, mu_start, tangent_mu)
        end if
        if (this%switch_pending) then
            ! The branch leaves the bifurcation along the critical mode at constant load (to
            ! first order; a symmetric branch): the predictor goes along it, the corrector in
            ! the hyperplane normal to it, which the path just crossed does not meet nearby.
            this%tangent = this%mode
            tangent_mu = 0.0_rk
        end if

        ! Predictor, then Newton in the normal hyperplane.
        this%y = this%y_start + this%step * this%tangent
        mu = mu_start + this%step * tangent_mu
        this%iterations = 0
        do iteration = 0, this%settings%max_newton
            call residual(this, system, x, this%y, mu, this%f, ok)
            if (.not. ok) then
                why = 'the residual is invalid (NaN, an inverted element) at the load time ' // &
                    str_significant(mu * this%settings%load_scale, 8)
                return
            end if
            this%residual = maxval(abs(this%f))
            if (this%residual <= this%settings%newton_atol) exit
            if (iteration == this%settings%max_newton) then
                why = 'Newton did not converge in ' // str(this%settings%max_newton) // &
                    ' iterations (|R| = ' // str_significant(this%residual, 3) // ')'
                return
            end if
            call factor(this, system, stepper, x, this%y, mu, ok, why, err)
            RS_RETURN_IF_ERROR(err)
            if (.not. ok) return
            this%iterations = this%iterations + 1
            call solve(stepper, this%f, this%a, ok, err)
            RS_RETURN_IF_ERROR(err)
            if (ok) call load_derivative(this, system, x, this%y, mu, ok)
            if (ok) call solve(stepper, this%f, this%b, ok, err)
            RS_RETURN_IF_ERROR(err)
            if (.not. ok) then
                why = 'a linear solve of the corrector failed'
                return
            end if
            ! a = -J^{-1} R, b = -J^{-1} R_mu.
            this%a = -this%a
            this%b = -this%b
            dmu = -weighted(this, this%tangent, this%a) / &
                (weighted(this, this%tangent, this%b) + tangent_mu)
            this%y = this%y + this%a + dmu * this%b
            mu = mu + dmu
        end do

        ! The corrector must stay near its predictor: one that went farther than the step
        ! itself converged on another part of the path (past a limit point, the far side of
        ! a snap-through), which a shorter step resolves.
        this%a = this%y - this%y_start - this%step * this%tangent
        turn = sqrt(weighted(this, this%a, this%a) + (mu - mu_start - this%step * tangent_mu)**2)
        if (turn > this%step) then
            why = 'the corrector went ' // str_significant(turn, 3) // ' from its predictor, ' // &
                'more than the step ' // str_significant(this%step, 3)
            return
        end if
        call system%load_step(mu * this%settings%load_scale, t_n, h)
        call system%update(t_n, h, x, this%y, this%x_new)
        measures = system%state_measures(this%x_new, from=x)
        turn = measures%largest_rotation
        if (turn > this%settings%max_rotation) then
            why = 'the step turned a section by ' // str_significant(turn, 3) // ' rad (at most ' // &
                str_significant(this%settings%max_rotation, 3) // ')'
            return
        end if
        this%secant = (this%y - this%y_start) / this%step
        this%secant_load = (mu - mu_start) / this%step
        this%has_secant = .true.
        if (this%switch_pending) then
            this%switch_pending = .false.
            this%switched = .true.
            ! The branch's first point: its critical mode is another one, no crossing.
            this%has_critical = .false.
            this%event = this%event // '; left the path for the branch that bifurcates there ' // &
                '(along its critical mode)'
        end if
        this%fresh = this%iterations > 0
        this%load = mu * this%settings%load_scale
        converged = .true.
    end subroutine try_step

    !> The critical eigenvalue at the current point: that of smallest modulus of J phi = kappa
    !> W phi, W = diag(path weights) with its forces in the equilibrium rows of their
    !> coordinates (rod_system_t%force_rows), by inverse iteration (phi <- J^-1 W phi) from the last
    !> point's mode, a few solves of the tangent's factorization per point (no factorization).
    !> The weights vanish on stresses, multipliers and rates, so these are the eigenvalues of J
    !> condensed on the nodes' positions and rotations, the constraints kept (phi_w tangent to
    !> them): the stiffness of the structure, positive definite where it is stable, its
    !> smallest eigenvalue crossing zero at a bifurcation or limit point. (Of J itself, a
    !> saddle point with ph_director's multipliers, the eigenvalues nearest zero came in pairs
    !> of either sign and the iteration did not settle: spurious crossings.) The modes are
    !> W-unit; this%critical = 1 / (phi . W J^-1 W phi).
    subroutine track_critical_mode(this, stepper, ok, err)
        type(arc_length_path_t), intent(inout) :: this
        type(rod_stepper_t), intent(inout) :: stepper
        logical, intent(out) :: ok
        type(error_t), allocatable, intent(out) :: err
        integer, parameter :: iterations = 3
        real(rk) :: quotient, norm
        integer :: k, i
        this%mode_before = this%mode
        this%critical_before = this%critical
        do k = 1, iterations
            ! The forces W phi, each in the equilibrium row of its coordinate.
            this%f_plus = 0.0_rk
            do i = 1, size(this%mode)
                this%f_plus(this%force_rows(i)) = this%f_plus(this%force_rows(i)) + &
                    this%weights(i) * this%mode(i)
            end do
            call solve(stepper, this%f_plus, this%a, ok, err)
            RS_RETURN_IF_ERROR(err)
            if (.not. ok) return
            quotient = weighted(this, this%mode, this%a)
            norm = sqrt(weighted(this, this%a, this%a))
            ok = norm > 0.0_rk
            if (.not. ok) return
            this%mode = this%a / norm
        end do
        ok = quotient /= 0.0_rk
        if (.not. ok) return
        this%critical = 1.0_rk / quotient
    end subroutine track_critical_mode

    !> A bifurcation between the last point and the current one (at mu, its tangent's load
    !> component tangent_mu): the critical eigenvalue changed sign, its mode stayed the same
    !> (|cos| > 0.9, not another eigenvalue taking over), and the tangent's load component kept
    !> its sign (at a limit point J is singular too, but the load turns there and the path
    !> passes it). With branch_switch the first one is switched to.
    subroutine check_bifurcation(this, mu, tangent_mu)
        type(arc_length_path_t), intent(inout) :: this
        real(rk), intent(in) :: mu, tangent_mu
        real(rk), parameter :: same_mode = 0.9_rk
        real(rk) :: previous
        logical :: crossed
        crossed = this%has_critical .and. this%critical * this%critical_before < 0.0_rk .and. &
            tangent_mu * this%tangent_load_before > 0.0_rk .and. &
            abs(weighted(this, this%mode, this%mode_before)) > same_mode
        this%has_critical = .true.
        previous = this%mu_before
        this%mu_before = mu
        this%tangent_load_before = tangent_mu
        if (.not. crossed) return
        this%bifurcations = this%bifurcations + 1
        ! Where the eigenvalue, linear in the load between the two points, vanishes.
        this%bifurcation_load = this%settings%load_scale * (previous + (mu - previous) * &
            this%critical_before / (this%critical_before - this%critical))
        this%event = 'crossed a bifurcation at the load time ' // &
            str_significant(this%bifurcation_load, 8) // ' (the smallest eigenvalue of the ' // &
            'tangent changed sign, the load did not turn)'
        if (.not. this%settings%branch_switch .or. this%switched) return
        this%switch_pending = .true.
    end subroutine check_bifurcation

    !> R(Y; lambda = mu t_end) into f; ok = false for an invalid state.
    subroutine residual(this, system, x, y, mu, f, ok)
        type(arc_length_path_t), intent(inout) :: this
        type(rod_system_t), intent(inout) :: system
        real(rk), intent(in) :: x(:), y(:), mu
        real(rk), intent(out) :: f(:)
        logical, intent(out) :: ok
        real(rk) :: t_n, h, load
        integer :: status
        load = mu * this%settings%load_scale
        call system%set_load_problem(load)
        call system%load_step(load, t_n, h)
        call system%step_residual(t_n, h, x, y, f, status)
        ok = status == state_valid .and. all(f == f)
    end subroutine residual

    !> R_mu = dR/dmu at (Y, mu) into this%f, which holds R(Y, mu) on entry: the difference
    !> (R(Y, mu + delta) - R(Y, mu)) / delta.
    subroutine load_derivative(this, system, x, y, mu, ok)
        type(arc_length_path_t), intent(inout) :: this
        type(rod_system_t), intent(inout) :: system
        real(rk), intent(in) :: x(:), y(:), mu
        logical, intent(out) :: ok
        !> The residual is affine in loads that are linear in the load time (their time
        !> functions' values), so the difference is exact but for round-off, which delta = 1e-4
        !> keeps near 1e-12 of the loads' rows; a load whose time function curves (a pulse)
        !> only makes R_mu, and so the corrector's convergence, inexact by O(delta).
        real(rk), parameter :: delta = 1.0e-4_rk
        call residual(this, system, x, y, mu + delta, this%f_plus, ok)
        this%f = (this%f_plus - this%f) / delta
        call system%set_load_problem(mu * this%settings%load_scale)
    end subroutine load_derivative

    !> The Jacobian dR/dY at (Y, mu) factored by the stepper's linear solver.
    subroutine factor(this, system, stepper, x, y, mu, ok, why, err)
        type(arc_length_path_t), intent(inout) :: this
        type(rod_system_t), intent(inout) :: system
        type(rod_stepper_t), intent(inout) :: stepper
        real(rk), intent(in) :: x(:), y(:), mu
        logical, intent(out) :: ok
        character(len=:), allocatable, intent(inout) :: why
        type(error_t), allocatable, intent(out) :: err
        real(rk) :: t_n, h, load
        integer :: status
        logical :: singular
        load = mu * this%settings%load_scale
        call system%set_load_problem(load)
        call system%load_step(load, t_n, h)
        call system%step_jacobian(t_n, h, x, y, this%values, status)
        ok = status == state_valid
        if (.not. ok) then
            why = 'the Jacobian is invalid at the load time ' // str_significant(load, 8)
            return
        end if
        call stepper%factor(this%values, singular, err)
        RS_RETURN_IF_ERROR(err)
        this%factorizations = this%factorizations + 1
        ok = .not. singular
        if (singular) why = 'the tangent stiffness is singular at the load time ' // &
            str_significant(load, 8) // ' (a bifurcation point?)'
    end subroutine factor

    subroutine solve(stepper, rhs, sol, ok, err)
        type(rod_stepper_t), intent(inout) :: stepper
        real(rk), intent(in) :: rhs(:)
        real(rk), intent(inout) :: sol(:)
        logical, intent(out) :: ok
        type(error_t), allocatable, intent(out) :: err
        logical :: failed
        call stepper%solve(rhs, sol, failed, err)
        ok = .not. failed .and. all(sol == sol)
    end subroutine solve

    !> u . w v: the scaled inner product of the path's norm.
    pure real(rk) function weighted(this, u, v)
        type(arc_length_path_t), intent(in) :: this
        real(rk), intent(in) :: u(:), v(:)
        weighted = sum(this%weights * u * v)
    end function weighted

end module rs_solver_arc_length
