#include "rs_macros.h"
!> The linearized equations of motion of a system about a state at rest, read from its step
!> Jacobians (issue 27 item 1; docs/theory/modes.md): for every formulation, couplings and
!> joints included, without a second implementation of any force.
!>
!> At a state X at rest, the step unknowns Y of that state (the predictor's) and the forces of
!> the midpoint t = t_n + h/2, the Jacobian J(h) = dF/dY of a midpoint step is a Laurent
!> polynomial in h whose coefficients are the matrices of the continuous linear system:
!> - first order (formulation_traits_t%modal_form = modal_first_order; ph_director), B x' +
!>   A x = 0 in the unknowns: row i of J is h^p_i (B_i / h + A_i / 2) (rates are differences
!>   over h, every force and constraint is taken at the midpoint; the factor h^p_i of rows
!>   scaled by h, ph_director's momentum rows, only scales the row);
!> - second order (modal_second_order; se3_pg), M q'' + C q' + K q = 0 in positions alone:
!>   J(h) = 2 M / h^2 + C / h + K / 2 (u_{n+1} = 2 dq / h - u_n).
!> - a one-step scheme other than the midpoint rule (modal_one_step; se3_strand, coefficients
!>   frozen at t_n): dF/dY = h^p (B/h + A_Y), dF/dX_n = h^p (-B/h + A_X)
!>   (rod_system_t%state_jacobian), a first-order pencil with a0 = A_Y + A_X, a1 = B, read from
!>   a second fit of dF/dY + dF/dX_n (classify_one_step_row).
!> All are the pencil P(s) = a0 + s a1 + s^2 a2 (first order: a0 = A, a1 = B, a2 = 0; second
!> order, rows doubled: a0 = 4 C_0 = K, a1 = 2 C_1 = C, a2 = C_2 = M, with C_k the coefficient
!> of h^-k), whose eigenvalues s = +-i omega are the modes. Constraint rows (tie rows, rigid
!> strain components) have one power of h only: they are algebraic rows of a0, whatever their
!> factor (a scaled row or column leaves the eigenvalues as they are).
!>
!> The coefficients come from Jacobians at four steps h = 1/z, z = z0 (1, -1, 2, -2), solved
!> entry by entry for the powers h^1 .. h^-2; a fifth Jacobian at z = 3 z0 must agree with
!> them to round-off, else the formulation's step is not of this form there (a scheme other
!> than the midpoint rule, loads or drives that move with t, a state not at rest) and the
!> linearization is refused. z0 is chosen so that the powers weigh alike (balanced_z0, from
!> z0 = 1 / dt until it settles), and the rows with two powers are read once more at steps
!> where each term dominates (refine).
!>
!> Linearized buckling (buckling_stiffness) needs the tangent stiffness alone, of the reference
!> and of the loaded equilibrium: read from the system's static problem where the formulation
!> has one whose Jacobian is K_T (formulation_traits_t%static_tangent: ph_director), else from
!> one long dynamic step of a second-order pencil (static_stiffness).
!>
!> Pure Fortran on the system layer (rs_system_rod_system): no PETSc; the eigen solve is
!> src/solver/modal_solver.F90's.
module rs_system_linearization
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: str, str_significant
    use rs_formulations_formulation, only: formulation_traits_t, state_valid, modal_none, &
        modal_first_order, modal_second_order, modal_one_step
    use rs_system_rod_system, only: rod_system_t
    implicit none
    private

    public :: linearize_system, buckling_stiffness, equilibrate, balance_weight

    !> The linear pencil P(s) = a0 + s a1 + s^2 a2 of a system about a state at rest, on the
    !> system's Jacobian pattern (0-based CSR over its step unknowns).
    type, public :: pencil_t
        !> modal_first_order (a2 = 0) or modal_second_order.
        integer :: form = modal_none
        integer :: n = 0
        integer, allocatable :: row_ptr(:), cols(:)
        real(rk), allocatable :: a0(:), a1(:), a2(:)
        !> The largest relative disagreement of the fifth Jacobian with the fit.
        real(rk) :: fit_error = 0.0_rk
        !> |F(Y; X)|_inf / (|J|_max |Y|_inf) at z0: zero at an equilibrium.
        real(rk) :: unbalance = 0.0_rk
        !> Rows that are algebraic (one power of h: constraints).
        integer :: n_algebraic = 0
        !> The balanced z0 (1/s).
        real(rk) :: z0 = 0.0_rk
        !> a0 is a tangent stiffness read for linearized buckling (buckling_stiffness).
        logical :: stiffness = .false.
        !> First order in rates and stresses without positions (modal_one_step: se3_strand's
        !> intrinsic state): a rigid motion is one zero eigenvalue, not a Jordan block of two,
        !> and every real eigenvalue is a mode of its own.
        logical :: simple_zeros = .false.
    end type pencil_t

    !> Powers of h of the fit, and the sample points z / z0 (the last one checks).
    integer, parameter :: powers(4) = [1, 0, -1, -2]
    real(rk), parameter :: samples(5) = [1.0_rk, -1.0_rk, 2.0_rk, -2.0_rk, 3.0_rk]
    !> A power is present in a row when its terms reach this share of the row's largest
    !> sample entry (the fit's round-off is ~1e-14 of it).
    real(rk), parameter :: presence_tol = 1.0e-10_rk
    !> The smallest share of an entry's largest term that balanced_z0 takes into account.
    real(rk), parameter :: balance_tol = 1.0e-14_rk
    !> The largest relative disagreement of the check Jacobian that is round-off.
    real(rk), parameter :: fit_tol = 1.0e-8_rk
    !> The most sweeps of equilibrate (it settles in about log2 of the entries' spread).
    integer, parameter :: max_equilibration_sweeps = 100

contains

    !> The pencil of `system` about the state x (at rest) with the loads of time t; `dt` is the
    !> scene's step, the first guess of the time scale.
    subroutine linearize_system(system, t, x, dt, pencil, err)
        type(rod_system_t), intent(inout) :: system
        real(rk), intent(in) :: t, x(:), dt
        type(pencil_t), intent(out) :: pencil
        type(error_t), allocatable, intent(out) :: err
        type(formulation_traits_t) :: traits
        real(rk), allocatable :: coefficients(:, :), row_scale(:), total(:, :), total_scale(:)
        real(rk) :: z0, z_new
        character(len=:), allocatable :: message
        integer :: pass
        integer, parameter :: max_passes = 6
        traits = system%traits()
        if (traits%modal_form == modal_none) then
            message = 'modal analysis is not available for ' // system%formulation // &
                ': its step Jacobian at rest is not the linearized equations of motion ' // &
                '(docs/theory/modes.md)'
            RS_SET_ERROR(err, 'linearize_system', message)
            return
        end if
        ! A one-step scheme's pencil is first order; its A needs dF/dX_n as well (fit with_state).
        pencil%form = merge(modal_first_order, traits%modal_form, &
            traits%modal_form == modal_one_step)
        pencil%simple_zeros = traits%modal_form == modal_one_step
        pencil%n = system%n_unknown()
        call system%jacobian_pattern(pencil%row_ptr, pencil%cols)
        ! Rebalance z0 from the coefficients of the pass before until it settles (a stiff rod
        ! whose 1/dt is far below its elements' frequencies: se3_pg with 200 elements and dt =
        ! 0.25 starts with the mass terms at 1e-11 of the stiffness's).
        z0 = 1.0_rk / dt
        do pass = 1, max_passes
            call fit(system, t, x, z0, pencil, coefficients, row_scale, err)
            RS_RETURN_IF_ERROR(err)
            if (pass == max_passes) exit
            z_new = balanced_z0(coefficients, z0)
            if (abs(z_new / z0 - 1.0_rk) < 0.1_rk) exit
            z0 = z_new
        end do
        pencil%z0 = z0
        call refine(system, t, x, z0, pencil, coefficients, row_scale, err)
        RS_RETURN_IF_ERROR(err)
        if (traits%modal_form == modal_one_step) then
            call fit(system, t, x, z0, pencil, total, total_scale, err, with_state=.true.)
            RS_RETURN_IF_ERROR(err)
            call classify(pencil, coefficients, row_scale, z0, err, total, total_scale)
        else
            call classify(pencil, coefficients, row_scale, z0, err)
        end if
        RS_RETURN_IF_ERROR(err)
        if (all(pencil%a1 == 0.0_rk) .and. all(pencil%a2 == 0.0_rk)) then
            message = 'the equations of motion have no inertia: give the rods a density ' // &
                '(or rhoA, rhoI1, rhoI2)'
            RS_SET_ERROR(err, 'linearize_system', message)
        end if
    end subroutine linearize_system

    !> The stiffnesses of linearized buckling (docs/theory/modes.md), K_0 phi = -lambda K_geo
    !> phi, as the a0 of two pencils on the system's pattern: `reference`, K_0 at the unloaded
    !> initial state x_0 with the loads of t = 0, and `geometric`, K_geo, the stiffness the
    !> loads of t add (x's load time: the load pattern) for the run's equilibrium x. Read
    !> - where the formulation's static problem has K_T as its Jacobian (traits%static_tangent:
    !>   ph_director in a quasistatic run), from that Jacobian (static_tangent): K_geo =
    !>   K_T(x) - K_0;
    !> - for a second-order pencil (traits%modal_form; the system built for dynamics), from
    !>   linearize_system's pencils with their stiffness rows read again from one long step
    !>   each (static_stiffness), the same rows in both: K_geo the stress stiffness of x's
    !>   stresses at x_0 with the loads' own tangents where the formulation can hold its
    !>   stresses (rod_system_t%stress_only: se3_pg, whose difference of tangents turns a
    !>   twisted section's stiffness into a load, Greenhill's shaft), else K_T(x) - K_0
    !>   (ph_planar);
    !> and refused otherwise. x becomes the state the modes are drawn about (x_0 with the
    !> stresses held, or x itself; unbalance set there). `dt` is the scene's step
    !> (linearize_system's first time scale).
    subroutine buckling_stiffness(system, t, x, dt, reference, geometric, err)
        type(rod_system_t), intent(inout) :: system
        real(rk), intent(in) :: t, dt
        real(rk), intent(inout) :: x(:)
        type(pencil_t), intent(out) :: reference, geometric
        type(error_t), allocatable, intent(out) :: err
        type(formulation_traits_t) :: traits
        real(rk), allocatable :: x0(:), about(:)
        logical, allocatable :: rows(:)
        logical :: stressed, restored
        character(len=:), allocatable :: message
        allocate(x0(size(x)))
        call system%initial_state(x0)
        traits = system%traits()
        if (traits%static_tangent) then
            call static_tangent(system, 0.0_rk, x0, reference, err)
            RS_RETURN_IF_ERROR(err)
            call static_tangent(system, t, x, geometric, err)
            RS_RETURN_IF_ERROR(err)
            geometric%a0 = geometric%a0 - reference%a0
            return
        end if
        if (traits%modal_form /= modal_second_order) then
            message = 'linearized buckling is not available for ' // system%formulation // &
                ': neither a static problem whose Jacobian is the tangent stiffness nor a ' // &
                'second-order pencil to read it from (docs/theory/modes.md)'
            RS_SET_ERROR(err, 'buckling_stiffness', message)
            return
        end if
        call linearize_system(system, 0.0_rk, x0, dt, reference, err)
        RS_RETURN_IF_ERROR(err)
        about = x0
        call system%stress_only(stressed, about, x)
        if (.not. stressed) about = x
        call linearize_system(system, t, about, dt, geometric, err)
        if (.not. allocated(err)) then
            ! The fit's round-off is too large for the buckling mode.
            rows = mass_rows(reference) .or. mass_rows(geometric)
            call static_stiffness(system, t, about, rows, geometric, err)
        end if
        call system%stress_only(restored, x0)
        RS_RETURN_IF_ERROR(err)
        call static_stiffness(system, 0.0_rk, x0, rows, reference, err)
        RS_RETURN_IF_ERROR(err)
        if (reference%n /= geometric%n) then
            RS_SET_ERROR(err, 'buckling_stiffness', 'the loaded and unloaded pencils differ in size')
            return
        end if
        if (.not. stressed) geometric%a0 = geometric%a0 - reference%a0
        x = about
    end subroutine buckling_stiffness

    !> The tangent stiffness of `system` at x with the loads of t as the a0 of `pencil` (a1 =
    !> a2 = 0): the Jacobian of its static problem at load time t (set_step_problem; the
    !> system is set back to time steps), at the step h = 1 (rows of forces as a step of unit
    !> length, continue_equilibrium's scaling in rs_solver_rod_run), about the unknowns of x
    !> (the predictor's: the static problem's Y is its state's). For ph_director the mixed
    !> static problem of methods/ph_director_3d.md §2.8 (eqs. 96e-g): the rows of the
    !> momenta with the geometric stiffness of the stresses, multipliers and loads, the
    !> stress rows C sigma - int psi (eps(q) - eps_0) and the constraints g(d) = 0; the
    !> kinematic rows -h/2 (v_1 - v_n) give v = 0 in any buckling mode. The unbalance is that
    !> of the static residual at x (zero at the run's equilibrium).
    subroutine static_tangent(system, t, x, pencil, err)
        type(rod_system_t), intent(inout) :: system
        real(rk), intent(in) :: t, x(:)
        type(pencil_t), intent(out) :: pencil
        type(error_t), allocatable, intent(out) :: err
        real(rk), allocatable :: y(:), f(:)
        integer :: status
        pencil%stiffness = .true.
        pencil%n = system%n_unknown()
        call system%jacobian_pattern(pencil%row_ptr, pencil%cols)
        allocate(pencil%a0(size(pencil%cols)), y(pencil%n), f(pencil%n))
        call system%set_step_problem(.true., t)
        call system%predictor(0.0_rk, 1.0_rk, x, y)
        call system%step_jacobian(0.0_rk, 1.0_rk, x, y, pencil%a0, status)
        if (status == state_valid) call system%step_residual(0.0_rk, 1.0_rk, x, y, f, status)
        call system%set_step_problem(.false., t)
        if (status /= state_valid) then
            RS_SET_ERROR(err, 'static_tangent', 'the state is invalid (NaN, an inverted element)')
            return
        end if
        allocate(pencil%a1(size(pencil%cols)), pencil%a2(size(pencil%cols)), source=0.0_rk)
        pencil%unbalance = maxval(abs(f)) / max(tiny(1.0_rk), maxval(abs(pencil%a0)) * &
            max(maxval(abs(y)), tiny(1.0_rk)))
    end subroutine static_tangent

    !> The stiffness rows of a second-order `pencil` (linearize_system's, of `system` about x
    !> with the loads of t) read again from one Jacobian at a step so long that the mass terms
    !> are below round-off: J(h) = K / 2 + 2 M / h^2 at rest, so a0 = 4 J in `rows` (those with
    !> mass); the others, algebraic, keep the fit's a0. Linearized buckling (docs/theory/
    !> modes.md) needs the stiffness of the slowest mode, where the fit's a0 is not good
    !> enough: with it, the Euler load of a se3_pg cantilever (L / r = 1000) of 400 - 800
    !> elements moved by up to 3.5e-5 with the run's dt (z0 starts at 1/dt); with h = 1e8 /
    !> z0 the mass left, 2 M / h^2, raised it by (1 / (h omega_1))^2 (z0 grows with the mesh:
    !> 1e-5 at 800 elements). h is 1e20 / z0, but at most 1e8 |t| for t /= 0: the step's forces
    !> act at t_n + h / 2 = t, a sum that keeps t only to eps h / (2 |t|) (1e-8 of it; with h
    !> = 1e20 / z0 the loads of t = 1 were those of t = 0, and a dead moment's stiffness was
    !> lost); the mass then left is (1e-8 / (|t| omega_1))^2 of the stiffness. One Jacobian
    !> times 4, exactly: a Richardson step that removed 2 M / h^2 from two of them cost the
    !> Euler load at 400 elements 5e-6 of round-off (the entries' sums no longer cancel alike).
    subroutine static_stiffness(system, t, x, rows, pencil, err)
        type(rod_system_t), intent(inout) :: system
        real(rk), intent(in) :: t, x(:)
        !> The rows to read again (mass_rows: of every pencil compared, so that a row is read
        !> alike in each; ph_planar's strain rows have mass in one state and not in another).
        logical, intent(in) :: rows(:)
        type(pencil_t), intent(inout) :: pencil
        type(error_t), allocatable, intent(out) :: err
        real(rk), allocatable :: y(:), values(:)
        real(rk) :: h
        integer :: i, lo, hi, status
        if (pencil%form /= modal_second_order) then
            RS_SET_ERROR(err, 'static_stiffness', 'not a second-order pencil')
            return
        end if
        h = 1.0e20_rk / pencil%z0
        if (t /= 0.0_rk) h = min(h, 1.0e8_rk * abs(t))
        allocate(y(pencil%n), values(size(pencil%cols)))
        call system%predictor(t - 0.5_rk * h, h, x, y)
        call system%step_jacobian(t - 0.5_rk * h, h, x, y, values, status)
        if (status /= state_valid) then
            RS_SET_ERROR(err, 'static_stiffness', 'the state is invalid (NaN, an inverted element)')
            return
        end if
        do i = 1, pencil%n
            lo = pencil%row_ptr(i) + 1
            hi = pencil%row_ptr(i + 1)
            if (hi < lo) cycle
            if (.not. rows(i)) cycle
            pencil%a0(lo:hi) = 4.0_rk * values(lo:hi)
        end do
        pencil%stiffness = .true.
    end subroutine static_stiffness

    !> The rows of `pencil` with mass (a2 /= 0 in the row).
    pure function mass_rows(pencil) result(rows)
        type(pencil_t), intent(in) :: pencil
        logical :: rows(pencil%n)
        integer :: i
        do i = 1, pencil%n
            rows(i) = any(pencil%a2(pencil%row_ptr(i) + 1:pencil%row_ptr(i + 1)) /= 0.0_rk)
        end do
    end function mass_rows

    !> The z0 at which the terms of neighbouring powers of h weigh alike: the geometric mean
    !> over the entries with two powers or more of the crossover (|C_hi| / |C_lo|)^(1 / (p_hi
    !> - p_lo)) of their highest and lowest power (for an entry of M and K, about the highest
    !> frequency of the elements). The fit's round-off in an entry is that of its largest term
    !> at z0, so the minor term of an entry keeps most digits when z0 is near its crossover;
    !> an entry with one power is exact at any z0 (the kinematic identities). A term counts
    !> from 1e-14 of its entry's largest (it is then known to a few digits, enough for its
    !> crossover). z0 unchanged when no entry has two powers.
    pure real(rk) function balanced_z0(coefficients, z0) result(z)
        real(rk), intent(in) :: coefficients(:, :), z0
        real(rk) :: weight(4), largest, sum_log
        integer :: j, hi, lo, n
        sum_log = 0.0_rk
        n = 0
        do j = 1, size(coefficients, 1)
            weight = abs(coefficients(j, :)) * z0**(-powers)
            largest = maxval(weight)
            if (largest <= 0.0_rk) cycle
            if (count(weight > balance_tol * largest) < 2) cycle
            hi = findloc(weight > balance_tol * largest, .true., dim=1)
            lo = findloc(weight > balance_tol * largest, .true., dim=1, back=.true.)
            sum_log = sum_log + log(abs(coefficients(j, hi)) / abs(coefficients(j, lo))) / &
                real(powers(hi) - powers(lo), rk)
            n = n + 1
        end do
        z = z0
        if (n > 0) z = exp(sum_log / real(n, rk))
    end function balanced_z0

    !> Jacobians at z0 * samples, the coefficients of h^powers entry by entry (nnz x 4), each
    !> row's largest sample entry, the check against the fifth sample and the unbalance.
    !> `with_state`: of dF/dY + dF/dX_n (a one-step scheme's total, modal_one_step).
    subroutine fit(system, t, x, z0, pencil, coefficients, row_scale, err, with_state)
        type(rod_system_t), intent(inout) :: system
        real(rk), intent(in) :: t, x(:), z0
        type(pencil_t), intent(inout) :: pencil
        real(rk), allocatable, intent(out) :: coefficients(:, :), row_scale(:)
        type(error_t), allocatable, intent(out) :: err
        logical, intent(in), optional :: with_state
        real(rk) :: vandermonde(4, 4), inverse(4, 4), z, h, worst, scale
        real(rk), allocatable :: values(:, :), y(:), y_first(:), f(:), state(:)
        character(len=:), allocatable :: message
        integer :: k, j, status, nnz, i
        logical :: total
        total = .false.
        if (present(with_state)) total = with_state
        nnz = size(pencil%cols)
        allocate(values(nnz, 5), y(pencil%n), f(pencil%n), state(nnz))
        do k = 1, 5
            z = z0 * samples(k)
            h = 1.0_rk / z
            ! The forces of the midpoint step act at t_n + h/2 = t.
            call system%predictor(t - 0.5_rk * h, h, x, y)
            if (k == 1) then
                y_first = y
            else if (any(abs(y - y_first) > 1.0e-12_rk * max(1.0_rk, maxval(abs(y_first))))) then
                message = 'the state is not at rest (the step''s first iterate depends on ' // &
                    'the step): modes are computed about a state at rest'
                RS_SET_ERROR(err, 'linearize_system', message)
                return
            end if
            call system%step_jacobian(t - 0.5_rk * h, h, x, y, values(:, k), status)
            if (status /= state_valid) then
                RS_SET_ERROR(err, 'linearize_system', 'the state is invalid (NaN, an inverted element)')
                return
            end if
            if (total) then
                call system%state_jacobian(t - 0.5_rk * h, h, x, y, state, status)
                if (status /= state_valid) then
                    message = 'modal analysis of ' // system%formulation // ' needs the ' // &
                        'derivative of its step by the state at t_n, which it gives for one ' // &
                        'rod without couplings or dead loads (docs/theory/modes.md)'
                    RS_SET_ERROR(err, 'linearize_system', message)
                    return
                end if
                values(:, k) = values(:, k) + state
            end if
            if (k == 1) then
                call system%step_residual(t - 0.5_rk * h, h, x, y, f, status)
                pencil%unbalance = maxval(abs(f)) / max(tiny(1.0_rk), &
                    maxval(abs(values(:, 1))) * max(maxval(abs(y)), tiny(1.0_rk)))
            end if
        end do
        do k = 1, 4
            do j = 1, 4
                vandermonde(k, j) = (z0 * samples(k))**(-powers(j))
            end do
        end do
        call invert4(vandermonde, inverse)
        coefficients = matmul(values(:, 1:4), transpose(inverse))
        allocate(row_scale(pencil%n), source=0.0_rk)
        worst = 0.0_rk
        do i = 1, pencil%n
            j = pencil%row_ptr(i) + 1
            k = pencil%row_ptr(i + 1)
            if (k < j) cycle
            row_scale(i) = maxval(abs(values(j:k, 1:5)))
            scale = max(row_scale(i), tiny(1.0_rk))
            worst = max(worst, maxval(abs(values(j:k, 5) - matmul(coefficients(j:k, :), &
                (z0 * samples(5))**(-powers)))) / scale)
        end do
        pencil%fit_error = worst
        if (worst > fit_tol) then
            message = 'the step Jacobian of ' // system%formulation // ' at this state is not ' // &
                'of the midpoint form in h (a Jacobian at a fifth step differs from the fit by ' // &
                str_significant(worst, 3) // ' of its entries): loads or drives that change ' // &
                'with time, or a state not at rest (docs/theory/modes.md)'
            RS_SET_ERROR(err, 'linearize_system', message)
        end if
    end subroutine fit

    !> Row and column scalings D_r, D_c of `pencil` at the frequency `weight` (1/s), for the
    !> eigen solve (src/solver/modal_solver.F90, docs/theory/modes.md): Ruiz's simultaneous
    !> equilibration (each sweep divides every row and column by about the square root of its
    !> largest entry) of |a0| + w |a1| + w^2 |a2|, the pencil's magnitude at |s| = w, with w =
    !> balance_weight(weight), until the largest entry of every row and column of D_r |P| D_c
    !> is within a factor 2 of 1. Every factor is a power of 2, so D_r P(s) D_c has exactly the
    !> eigenvalues of P (its eigenvectors y, P's x = D_c y). An empty row or column keeps 1.
    pure subroutine equilibrate(pencil, weight, row_scale, col_scale)
        type(pencil_t), intent(in) :: pencil
        real(rk), intent(in) :: weight
        real(rk), intent(out) :: row_scale(:), col_scale(:)
        real(rk), allocatable :: magnitude(:), row_max(:), col_max(:)
        real(rk) :: w, v
        integer :: sweep, i, j, k
        logical :: settled
        row_scale = 1.0_rk
        col_scale = 1.0_rk
        w = balance_weight(weight)
        magnitude = abs(pencil%a0) + w * abs(pencil%a1) + w**2 * abs(pencil%a2)
        allocate(row_max(pencil%n), col_max(pencil%n))
        do sweep = 1, max_equilibration_sweeps
            row_max = 0.0_rk
            col_max = 0.0_rk
            do i = 1, pencil%n
                do k = pencil%row_ptr(i) + 1, pencil%row_ptr(i + 1)
                    j = pencil%cols(k) + 1
                    v = row_scale(i) * magnitude(k) * col_scale(j)
                    row_max(i) = max(row_max(i), v)
                    col_max(j) = max(col_max(j), v)
                end do
            end do
            settled = .true.
            do i = 1, pencil%n
                call rescale(row_max(i), row_scale(i), settled)
                call rescale(col_max(i), col_scale(i), settled)
            end do
            if (settled) exit
        end do
    contains

        !> factor times 2^-round(log2(largest) / 2), about 1 / sqrt(largest), unless that is 1.
        pure subroutine rescale(largest, factor, settled)
            real(rk), intent(in) :: largest
            real(rk), intent(inout) :: factor
            logical, intent(inout) :: settled
            integer :: e
            if (largest <= 0.0_rk) return
            e = nint(0.5_rk * log(largest) / log(2.0_rk))
            if (e == 0) return
            factor = scale(factor, -e)
            settled = .false.
        end subroutine rescale
    end subroutine equilibrate

    !> The frequency equilibrate uses for `weight` (> 0): the nearest power of 2, so that
    !> weights differing in their last bits (an eigenvalue found on another number of ranks)
    !> scale the pencil alike.
    pure real(rk) function balance_weight(weight) result(w)
        real(rk), intent(in) :: weight
        w = 2.0_rk**nint(log(weight) / log(2.0_rk))
    end function balance_weight

    !> The pencil's a0, a1, a2 from the powers present in each row (module header). With
    !> `total` and `total_scale`, the coefficients of dF/dY + dF/dX_n of a one-step scheme
    !> (modal_one_step, classify_one_step_row).
    subroutine classify(pencil, coefficients, row_scale, z0, err, total, total_scale)
        type(pencil_t), intent(inout) :: pencil
        real(rk), intent(in) :: coefficients(:, :), row_scale(:), z0
        type(error_t), allocatable, intent(out) :: err
        real(rk), intent(in), optional :: total(:, :), total_scale(:)
        logical :: has(4)
        character(len=:), allocatable :: message
        integer :: i, k, lo, hi
        allocate(pencil%a0(size(pencil%cols)), pencil%a1(size(pencil%cols)), &
            pencil%a2(size(pencil%cols)), source=0.0_rk)
        pencil%n_algebraic = 0
        do i = 1, pencil%n
            lo = pencil%row_ptr(i) + 1
            hi = pencil%row_ptr(i + 1)
            if (hi < lo) cycle
            has = row_powers(coefficients(lo:hi, :), row_scale(i), z0)
            if (present(total)) then
                call classify_one_step_row(pencil, lo, hi, has, coefficients(lo:hi, :), &
                    total(lo:hi, :), row_powers(total(lo:hi, :), max(row_scale(i), &
                    total_scale(i)), z0), message)
                if (.not. allocated(message)) cycle
                message = 'row ' // str(i) // ' of the step ' // message
                RS_SET_ERROR(err, 'linearize_system', message)
                return
            end if
            if (count(has) == 1) then
                ! One power: an algebraic row (a constraint), whatever its factor.
                k = findloc(has, .true., dim=1)
                pencil%a0(lo:hi) = coefficients(lo:hi, k)
                pencil%n_algebraic = pencil%n_algebraic + 1
                cycle
            end if
            if (pencil%form == modal_first_order) then
                ! h^p (B / h + A / 2): two neighbouring powers p (A / 2) and p - 1 (B).
                do k = 1, 3
                    if (has(k) .and. has(k + 1) .and. count(has) == 2) then
                        pencil%a0(lo:hi) = 2.0_rk * coefficients(lo:hi, k)
                        pencil%a1(lo:hi) = coefficients(lo:hi, k + 1)
                        exit
                    end if
                end do
                if (k <= 3) cycle
            else if (.not. has(1)) then
                ! 2 M / h^2 + C / h + K / 2, doubled; an absent power is round-off, dropped.
                if (has(2)) pencil%a0(lo:hi) = 4.0_rk * coefficients(lo:hi, 2)
                if (has(3)) pencil%a1(lo:hi) = 2.0_rk * coefficients(lo:hi, 3)
                if (has(4)) pencil%a2(lo:hi) = coefficients(lo:hi, 4)
                cycle
            end if
            message = 'row ' // str(i) // ' of the step Jacobian has the powers of h ' // &
                powers_text(has) // ', which a ' // trim(merge('first ', 'second', &
                pencil%form == modal_first_order)) // '-order midpoint step does not have ' // &
                '(docs/theory/modes.md)'
            RS_SET_ERROR(err, 'linearize_system', message)
            return
        end do
    end subroutine classify

    !> Entries lo:hi of the pencil of a one-step scheme (modal_one_step) from the powers and
    !> coefficients of the row in dF/dY (`has`, `coefficients`) and in dF/dY + dF/dX_n
    !> (`has_total`, `total`): a row h^p (B / h + A_Y) of dF/dY with dF/dX_n = h^p (-B / h
    !> + A_X) gives a1 = B and a0 = A_Y + A_X, the total's h^p coefficient, whose h^(p-1) one
    !> must vanish (the scheme is consistent there: X_n and Y differ by h x'); a row with one
    !> power is algebraic, its a0 the total's coefficient of that power. `message` is
    !> allocated (the rest of an error text) when the row is of neither kind.
    subroutine classify_one_step_row(pencil, lo, hi, has, coefficients, total, &
            has_total, message)
        type(pencil_t), intent(inout) :: pencil
        integer, intent(in) :: lo, hi
        logical, intent(in) :: has(4), has_total(4)
        real(rk), intent(in) :: coefficients(:, :), total(:, :)
        character(len=:), allocatable, intent(out) :: message
        integer :: k
        k = findloc(has, .true., dim=1)
        if (count(has) == 1 .and. count(has_total .and. .not. has) == 0) then
            pencil%a0(lo:hi) = total(:, k)
            pencil%n_algebraic = pencil%n_algebraic + 1
            return
        end if
        if (count(has) == 2 .and. k < 4) then
            if (has(k + 1) .and. .not. has_total(k + 1)) then
                pencil%a0(lo:hi) = total(:, k)
                pencil%a1(lo:hi) = coefficients(:, k + 1)
                return
            end if
        end if
        message = 'has the powers of h ' // powers_text(has) // ' in dF/dY and ' // &
            powers_text(has_total) // ' in dF/dY + dF/dX_n, which a consistent ' // &
            'one-step scheme B x'' + A x = 0 does not have (docs/theory/modes.md)'
    end subroutine classify_one_step_row

    !> The powers of h present in a row (its entries' coefficients), by their terms at z0
    !> against the row's largest sample entry.
    pure function row_powers(coefficients, row_scale, z0) result(present)
        real(rk), intent(in) :: coefficients(:, :), row_scale, z0
        logical :: present(4)
        integer :: k
        do k = 1, 4
            present(k) = maxval(abs(coefficients(:, k))) * z0**(-powers(k)) > &
                presence_tol * row_scale
        end do
    end function row_powers

    !> The coefficients of the rows with two powers again, from Jacobians at z0 / spread and
    !> z0 spread, where each power's term dominates: the four-point fit leaves in both the
    !> round-off of the larger term at z0 (for M and K sharing entries, eps |K| in each entry,
    !> uncorrelated between entries), while J(z0 / spread) is the formulation's own tangent K/2
    !> plus a vanishing 2 M (z0 / spread)^2, with the round-off of an assembled K. Measured on
    !> se3_pg's cantilever with 600 elements: the first frequency's error against Timoshenko's
    !> 2.2e-7 after the fit alone (the h^2 trend says 3.4e-7: round-off of 1.2e-7 that moved
    !> with z0), 3.39e-7 after refine. (The rigid-body zeros of a free rod stay where they were:
    !> their floor is the tangent's own round-off, docs/theory/modes.md.)
    subroutine refine(system, t, x, z0, pencil, coefficients, row_scale, err)
        type(rod_system_t), intent(inout) :: system
        real(rk), intent(in) :: t, x(:), z0
        type(pencil_t), intent(in) :: pencil
        real(rk), intent(inout) :: coefficients(:, :)
        real(rk), intent(in) :: row_scale(:)
        type(error_t), allocatable, intent(out) :: err
        real(rk), parameter :: spread = 1.0e4_rk
        real(rk) :: z(2), values(size(coefficients, 1), 2), a(2, 2), det, h
        real(rk), allocatable :: y(:)
        logical :: present(4)
        integer :: i, j, k, lo, hi, first, second, status
        type(formulation_traits_t) :: traits
        traits = system%traits()
        z = [z0 / spread, z0 * spread]
        allocate(y(pencil%n))
        do k = 1, 2
            h = 1.0_rk / z(k)
            call system%predictor(t - 0.5_rk * h, h, x, y)
            call system%step_jacobian(t - 0.5_rk * h, h, x, y, values(:, k), status)
            if (status /= state_valid) then
                RS_SET_ERROR(err, 'linearize_system', 'the state is invalid (NaN, an inverted element)')
                return
            end if
        end do
        do i = 1, pencil%n
            lo = pencil%row_ptr(i) + 1
            hi = pencil%row_ptr(i + 1)
            if (hi < lo) cycle
            present = row_powers(coefficients(lo:hi, :), row_scale(i), z0)
            if (count(present) /= 2) cycle
            first = findloc(present, .true., dim=1)
            second = findloc(present, .true., dim=1, back=.true.)
            a(:, 1) = z**(-powers(first))
            a(:, 2) = z**(-powers(second))
            det = a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)
            do j = lo, hi
                coefficients(j, :) = 0.0_rk
                coefficients(j, first) = (a(2, 2) * values(j, 1) - a(1, 2) * values(j, 2)) / det
                coefficients(j, second) = (a(1, 1) * values(j, 2) - a(2, 1) * values(j, 1)) / det
            end do
        end do
    end subroutine refine

    function powers_text(present) result(text)
        logical, intent(in) :: present(4)
        character(len=:), allocatable :: text
        integer :: k
        text = ''
        do k = 1, 4
            if (.not. present(k)) cycle
            if (len(text) > 0) text = text // ', '
            text = text // str(powers(k))
        end do
    end function powers_text

    !> The inverse of a 4 x 4 matrix by Gauss-Jordan elimination with partial pivoting (the
    !> Vandermonde matrix of the samples, well conditioned).
    pure subroutine invert4(a, inverse)
        real(rk), intent(in) :: a(4, 4)
        real(rk), intent(out) :: inverse(4, 4)
        real(rk) :: work(4, 8), row(8)
        integer :: i, p, k
        work = 0.0_rk
        work(:, 1:4) = a
        do i = 1, 4
            work(i, 4 + i) = 1.0_rk
        end do
        do i = 1, 4
            p = i - 1 + maxloc(abs(work(i:4, i)), dim=1)
            row = work(p, :)
            work(p, :) = work(i, :)
            work(i, :) = row / row(i)
            do k = 1, 4
                if (k /= i) work(k, :) = work(k, :) - work(k, i) * work(i, :)
            end do
        end do
        inverse = work(:, 5:8)
    end subroutine invert4

end module rs_system_linearization
