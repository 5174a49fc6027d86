#include "rs_macros.h"
!> The modes of a system's linear pencil (rs_system_linearization) from SLEPc: the `bind(C)`
!> interface to src/solver/modal_solver.c, the one door to SLEPc (DESIGN.md §2), and the
!> eigenvalues turned into frequencies (docs/theory/modes.md).
!>
!> With P(s) = a0 + s a1 + s^2 a2, a mode is an eigenvalue s = -delta +- i omega: omega the
!> angular frequency (rad/s), delta the decay rate (1/s, zero without damping). A first-order
!> pencil gives every mode as two eigenvalues: an oscillating one as a conjugate pair (counted
!> once, omega = |Im mu|), a rigid-body mode as a double zero (a Jordan block of the first-
!> order form) that round-off splits into +-i epsilon (a pair, as before) or +-epsilon (two
!> real eigenvalues, paired: omega^2 = mu_1 mu_2), except in a state of rates and stresses
!> without positions (pencil_t%simple_zeros: se3_strand), where a rigid motion is one zero and
!> every real eigenvalue a mode of its own; a second-order undamped pencil gives
!> omega^2 directly. A negative omega^2 (an unstable state, or a rigid-body zero split to
!> -epsilon^2) is reported as a negative frequency.
module rs_solver_modal_solver
    use, intrinsic :: iso_c_binding, only: c_int, c_double, c_char
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_core_strings, only: str, from_c_string
    use rs_formulations_formulation, only: modal_first_order, modal_second_order
    use rs_system_linearization, only: pencil_t, equilibrate, balance_weight
    implicit none
    private

    public :: solve_modes, solve_buckling, slepc_version, lowest_elastic

    !> The modes found, lowest first.
    type, public :: modes_t
        integer :: n = 0
        !> Angular frequency omega (rad/s; negative: omega^2 < 0, an unstable mode) and decay
        !> rate delta (1/s) of each mode.
        real(rk), allocatable :: omega(:), decay(:)
        !> Buckling (solve_buckling): the load factor lambda of each mode, smallest |lambda|
        !> first (omega and decay zero).
        real(rk), allocatable :: load_factor(:)
        !> SLEPc's backward error of each eigenpair (of the equilibrated pencil).
        real(rk), allocatable :: residual(:)
        !> The eigenvectors in the step unknowns (n_unknown x n), real and imaginary parts,
        !> scaled to a largest modulus of 1. Their phase is free: the caller chooses it on the
        !> entries it shows (a first-order mode's velocities are a quarter period from its
        !> positions, so no single phase makes the whole vector real).
        real(rk), allocatable :: shape(:, :), shape_im(:, :)
        !> The solver as configured (after -modes_ options).
        character(len=:), allocatable :: solver
    end type modes_t

    interface
        integer(c_int) function rs_modes_solve(n, row_ptr, cols, a0, a1, a2, degree, n_wanted, &
                shift, n_found, mu_re, mu_im, vec_re, vec_im, errors, solver_text, text_len, &
                errmsg, errlen) bind(C)
            import :: c_int, c_double, c_char
            integer(c_int), value :: n, degree, n_wanted, text_len, errlen
            integer(c_int), intent(in) :: row_ptr(*), cols(*)
            real(c_double), intent(in) :: a0(*), a1(*), a2(*)
            real(c_double), value :: shift
            integer(c_int), intent(out) :: n_found
            real(c_double), intent(out) :: mu_re(*), mu_im(*), vec_re(*), vec_im(*), errors(*)
            character(kind=c_char), intent(out) :: solver_text(*), errmsg(*)
        end function rs_modes_solve
        subroutine rs_slepc_version(buffer, length) bind(C)
            import :: c_char, c_int
            character(kind=c_char), intent(out) :: buffer(*)
            integer(c_int), value :: length
        end subroutine rs_slepc_version
    end interface

    !> The shift of shift-and-invert, as a share of the pencil's frequency scale z0
    !> (rs_system_linearization: the elements' highest frequency where M and K share entries,
    !> else 1/dt). Any negative real shift returns the lowest modes in order (modal_solver.c),
    !> and a0 - sigma a1 is regular for a free rod (a0 singular); but a shift far above the
    !> wanted frequencies clusters their shifted-inverted eigenvalues 1/(mu - sigma) near
    !> 1/sigma, and Krylov-Schur stalls: with 1e-3 / dt, seed 004's 16 m tube (0.528 Hz, dt =
    !> 1e-6) found no mode in 500 restarts. A shift below them separates them as 1/omega.
    real(rk), parameter :: shift_share = 1.0e-6_rk
    !> An eigenvalue |mu| below this share of the shift is a zero at round-off (the rigid
    !> motions of pencil_t%simple_zeros: about 1e-15 of it).
    real(rk), parameter :: zero_share = 1.0e-6_rk
    !> The shift of a second-order pencil with rigid-body zeros, as a share of its lowest
    !> elastic frequency (solve_modes).
    real(rk), parameter :: rigid_shift_share = 0.1_rk
    !> The weight of solve_buckling's equilibration (equilibrated_solve), a load factor: the
    !> loads of a buckling run are a share of the critical ones, so the factors wanted are of
    !> order 1 and above. 1 and 1e3 gave the same factors in every case of
    !> tests/regression/modes/buckling.py; equilibrated, the se3_pg column's factors on 2
    !> ranks agree with those on 1 to 1e-12 (as assembled: 5e-10 - 6e-9 with the OpenBLAS
    !> kernel, against a bound of 1e-8).
    real(rk), parameter :: buckling_weight = 1.0_rk

contains

    !> The n_modes lowest modes of `pencil`. Collective on all ranks (the solve is distributed).
    !>
    !> The pencil is solved equilibrated (equilibrated_solve; docs/theory/modes.md, "The eigen
    !> solve"). As assembled, its unknowns (positions, velocities, multipliers, stresses) and
    !> its rows are in mixed units, which the Krylov solver's Euclidean norms weigh as numbers:
    !> the eigenvalues of ph_director's damped cantilever had normwise condition numbers of
    !> 1e13 - 1e16, and the round-off of the factorization decided digits that the tests
    !> measure: the damping ratio of the second member of each bending pair was off by up to
    !> 1.5e-4 (theory: tau omega_n / 2 exactly), and the torsion mode took up to 2.7e-8 of the
    !> nearby fifth bending pair's displacement, differently with each OpenBLAS kernel
    !> (Prescott, Sandybridge, Haswell, SkylakeX; scaling the rows alone did not help).
    !> Equilibrated at a frequency w near the modes, their condition numbers fall to 1e4 - 1e6
    !> and the two are at 1e-9 and 1e-11 on every kernel. A mode far above w is conditioned
    !> worse (w at 2e-3 of the torsion mode's frequency: its displacement back at 1e-9), and
    !> the rigid-body double zeros of a free rod split more as w rises above the first elastic
    !> frequency. For ph_director z0 is 1/dt (no entry has two powers), the scene's choice, not
    !> the rod's: so the modes are solved twice, first equilibrated at z0, then at the lowest
    !> elastic frequency that solve found (lowest_elastic; when it is above the shift and
    !> another power of 2 than z0).
    !>
    !> The shift is shift_share z0, far below the modes. A solve shifted instead to half the
    !> lowest elastic frequency was tried and dropped: it joined the split
    !> bending pair of ph_director's free rod (1.4e-6 apart with this shift, whose a0 - sigma
    !> a1 is nearly singular on the rigid-body Jordan blocks), but on the clamped tube of seed
    !> 004 the first frequency's error against Timoshenko's rose from 5e-7 to 9.5e-6 (the
    !> first-order pencil's eigenvalues are sensitive, condition about 1e5, and the Ritz
    !> residual grew from round-off to 2e-10 with the shift), and the rigid-body zeros rose from
    !> 1e-12 to 1e-8 of the first elastic frequency. A second-order pencil with rigid-body
    !> zeros is solved again shifted to a tenth of its lowest elastic frequency (below).
    subroutine solve_modes(pencil, n_modes, modes, err)
        type(pencil_t), intent(in) :: pencil
        integer, intent(in) :: n_modes
        type(modes_t), intent(out) :: modes
        type(error_t), allocatable, intent(out) :: err
        real(rk) :: sigma, shift, lowest
        integer :: degree
        character(len=:), allocatable :: why
        if (pencil%form == modal_second_order .and. any(pencil%a1 /= 0.0_rk)) then
            why = 'modes of a damped second-order system are not available yet (its quadratic ' // &
                'pencil): remove the damping for the modal analysis'
            RS_SET_ERROR(err, 'solve_modes', why)
            return
        end if
        degree = merge(1, 2, pencil%form == modal_first_order)
        sigma = shift_share * pencil%z0
        shift = merge(-sigma, -sigma**2, degree == 1)
        call eigen_solve(pencil, n_modes, shift, pencil%z0, modes, err)
        if (allocated(err)) return
        lowest = lowest_elastic(modes%omega(1:modes%n))
        if (lowest <= sigma) return
        if (degree == 2 .and. sigma < rigid_shift_share * lowest .and. &
                any(abs(modes%omega(1:modes%n)) < 1.0e-3_rk * lowest)) then
            ! Rigid-body zeros: K is singular and K + sigma^2 M nearly so at the tiny shift,
            ! whose inverse then spans 1 / sigma^2 (rigid) to 1 / omega^2: the elastic images
            ! lose eps omega^2 / sigma^2 (ph_planar's free rod at z0 = 1/dt = 1e4: the fourth
            ! frequency 5.6e-4 off, the tenth 1.4 % off at 20 elements, modes missed, with
            ! residuals of 1e-13). Shifted to a tenth of the lowest elastic frequency, they keep
            ! 1e-2 (omega_1 / omega)^2 of it.
            sigma = rigid_shift_share * lowest
            call eigen_solve(pencil, n_modes, -sigma**2, lowest, modes, err)
            return
        end if
        if (balance_weight(lowest) /= balance_weight(pencil%z0)) &
            call eigen_solve(pencil, n_modes, shift, lowest, modes, err)
    end subroutine solve_modes

    !> The n_modes load factors lambda nearest zero of linearized buckling (issue 27 item 2,
    !> docs/theory/modes.md): K_0 phi = -lambda K_geo phi, K_0 the tangent stiffness of the
    !> reference state (pencil `reference`, unloaded) and K_geo the stiffness the loads add
    !> (`geometric`), both the a0 of rs_system_linearization's buckling_stiffness on the same
    !> pattern. Solved as the generalized problem Op0 = K_0, Op1 = -K_geo with shift-and-invert
    !> at 0 (K_0 is factorized: a system with rigid-body motions has none, and is refused by
    !> MUMPS), equilibrated at the load factor buckling_weight (solve_modes says why). The
    !> geometric stiffness is singular (axial and torsional rows barely change; the algebraic
    !> rows of a mixed K_T, ph_director's constraints, stress and kinematic rows, hardly or
    !> not at all), its infinite eigenvalues lie far from the target. Complex pairs (a
    !> non-conservative load) are skipped. Collective on all ranks.
    subroutine solve_buckling(reference, geometric, n_modes, modes, err)
        type(pencil_t), intent(in) :: reference, geometric
        integer, intent(in) :: n_modes
        type(modes_t), intent(out) :: modes
        type(error_t), allocatable, intent(out) :: err
        type(pencil_t) :: pencil
        type(modes_t) :: found
        character(len=:), allocatable :: why
        integer :: i
        if (.not. (reference%stiffness .and. geometric%stiffness)) then
            why = 'linearized buckling needs the tangent stiffnesses of buckling_stiffness'
            RS_SET_ERROR(err, 'solve_buckling', why)
            return
        end if
        if (reference%n /= geometric%n .or. size(reference%cols) /= size(geometric%cols)) then
            RS_SET_ERROR(err, 'solve_buckling', 'the loaded and unloaded pencils differ in pattern')
            return
        end if
        if (any(reference%cols /= geometric%cols)) then
            RS_SET_ERROR(err, 'solve_buckling', 'the loaded and unloaded pencils differ in pattern')
            return
        end if
        pencil = reference
        pencil%form = modal_first_order
        pencil%a1 = -geometric%a0
        pencil%a2 = 0.0_rk * reference%a0
        call eigen_solve_real(pencil, n_modes, found, err)
        if (allocated(err)) return
        modes = found
    contains

        !> Op0 x = mu Op1 x, the n_modes real eigenvalues nearest 0.
        subroutine eigen_solve_real(pencil, n_modes, modes, err)
            type(pencil_t), intent(in) :: pencil
            integer, intent(in) :: n_modes
            type(modes_t), intent(out) :: modes
            type(error_t), allocatable, intent(out) :: err
            real(rk), allocatable :: mu_re(:), mu_im(:), vec_re(:, :), vec_im(:, :), errors(:)
            character(kind=c_char) :: text(256), message(1024)
            integer(c_int) :: ierr, n_found
            integer :: n_wanted
            real(rk) :: scale
            n_wanted = min(n_modes + 2, pencil%n)
            allocate(mu_re(n_wanted), mu_im(n_wanted), errors(n_wanted), &
                vec_re(pencil%n, n_wanted), vec_im(pencil%n, n_wanted))
            call equilibrated_solve(pencil, 1, n_wanted, 0.0_rk, buckling_weight, n_found, &
                mu_re, mu_im, vec_re, vec_im, errors, text, message, ierr)
            if (ierr /= 0) then
                why = from_c_string(message) // ' (linearized buckling factorizes the ' // &
                    'unloaded stiffness: the system must be supported against rigid motion)'
                RS_SET_ERROR(err, 'solve_buckling', why)
                return
            end if
            modes%solver = from_c_string(text)
            allocate(modes%omega(n_modes), modes%decay(n_modes), modes%residual(n_modes), &
                modes%load_factor(n_modes), modes%shape(pencil%n, n_modes), &
                modes%shape_im(pencil%n, n_modes), source=0.0_rk)
            modes%n = 0
            do i = 1, n_found
                if (modes%n == n_modes) exit
                if (abs(mu_im(i)) > 1.0e-8_rk * abs(mu_re(i))) cycle
                modes%n = modes%n + 1
                modes%load_factor(modes%n) = mu_re(i)
                modes%residual(modes%n) = errors(i)
                scale = maxval(abs(vec_re(:, i)))
                if (scale <= 0.0_rk) scale = 1.0_rk
                modes%shape(:, modes%n) = vec_re(:, i) / scale
            end do
            if (modes%n < n_modes) then
                why = 'SLEPc found ' // str(modes%n) // ' real buckling load factors of the ' // &
                    str(n_modes) // ' asked for, and ' // str(count(abs(mu_im(1:n_found)) > &
                    1.0e-8_rk * abs(mu_re(1:n_found)))) // ' complex ones (a non-conservative ' // &
                    'load pattern, such as a dead end moment on an end free to turn, has no ' // &
                    'divergence there); ask for fewer modes'
                RS_SET_ERROR(err, 'solve_buckling', why)
            end if
        end subroutine eigen_solve_real
    end subroutine solve_buckling

    !> The lowest frequency |omega| above the rigid-body zeros: the first after a jump of a
    !> factor 1e3 between neighbours sorted by |omega| (the zeros are round-off: at most 2.4e-5
    !> of the first elastic frequency, se3_pg's free rod; neighbouring elastic modes are within
    !> a factor 10), or the lowest of all without such a jump; 0 when all are zero.
    pure real(rk) function lowest_elastic(omega) result(lowest)
        real(rk), intent(in) :: omega(:)
        real(rk) :: w(size(omega)), swap
        integer :: i, j
        w = abs(omega)
        do i = 2, size(w)
            do j = i, 2, -1
                if (w(j) >= w(j - 1)) exit
                swap = w(j)
                w(j) = w(j - 1)
                w(j - 1) = swap
            end do
        end do
        lowest = w(1)
        do i = 2, size(w)
            if (w(i) > 1.0e3_rk * w(i - 1)) then
                lowest = w(i)
                exit
            end if
        end do
    end function lowest_elastic

    !> The n_modes modes nearest the real shift `shift` (module header), of the pencil
    !> equilibrated at the frequency `weight` (solve_modes).
    subroutine eigen_solve(pencil, n_modes, shift, weight, modes, err)
        type(pencil_t), intent(in) :: pencil
        integer, intent(in) :: n_modes
        real(rk), intent(in) :: shift, weight
        type(modes_t), intent(out) :: modes
        type(error_t), allocatable, intent(out) :: err
        real(rk), allocatable :: mu_re(:), mu_im(:), vec_re(:, :), vec_im(:, :), errors(:)
        character(kind=c_char) :: text(256), message(1024)
        integer(c_int) :: ierr, found
        integer :: n_wanted, degree, i, pending
        character(len=:), allocatable :: why
        degree = merge(1, 2, pencil%form == modal_first_order)
        ! A first-order pencil gives every mode twice (a conjugate pair, or a rigid double zero).
        n_wanted = min(merge(2 * n_modes + 2, n_modes, degree == 1), pencil%n)
        allocate(mu_re(n_wanted), mu_im(n_wanted), errors(n_wanted), &
            vec_re(pencil%n, n_wanted), vec_im(pencil%n, n_wanted))
        call equilibrated_solve(pencil, degree, n_wanted, shift, weight, found, mu_re, mu_im, &
            vec_re, vec_im, errors, text, message, ierr)
        if (ierr /= 0) then
            RS_SET_ERROR(err, 'eigen_solve', from_c_string(message))
            return
        end if
        modes%solver = from_c_string(text)
        allocate(modes%omega(n_modes), modes%decay(n_modes), modes%residual(n_modes), &
            modes%shape(pencil%n, n_modes), modes%shape_im(pencil%n, n_modes))
        modes%n = 0
        pending = 0
        i = 1
        do while (i <= found .and. modes%n < n_modes)
            if (degree == 2) then
                call add_mode(sign(sqrt(abs(mu_re(i))), mu_re(i)), 0.0_rk, errors(i), &
                    vec_re(:, i), 0.0_rk * vec_re(:, i))
                i = i + 1
            else if (mu_im(i) /= 0.0_rk .and. pencil%simple_zeros .and. &
                    hypot(mu_re(i), mu_im(i)) < zero_share * abs(shift)) then
                ! Two simple zeros (rigid motions of a state of rates and stresses) that
                ! round-off turned into a conjugate pair: two modes, its real and imaginary
                ! parts spanning their motions.
                call add_mode(abs(mu_im(i)), mu_re(i), errors(i), vec_re(:, i), 0.0_rk * vec_re(:, i))
                if (modes%n < n_modes) call add_mode(abs(mu_im(i)), mu_re(i), errors(i), &
                    vec_im(:, i), 0.0_rk * vec_re(:, i))
                i = i + 2
            else if (mu_im(i) /= 0.0_rk) then
                ! mu = -s = delta -+ i omega; its conjugate follows it (real SLEPc).
                call add_mode(abs(mu_im(i)), mu_re(i), errors(i), vec_re(:, i), vec_im(:, i))
                i = i + 2
            else if (pencil%simple_zeros) then
                ! A state of rates and stresses: a real eigenvalue is a mode, s = -mu.
                call add_mode(0.0_rk, mu_re(i), errors(i), vec_re(:, i), 0.0_rk * vec_re(:, i))
                i = i + 1
            else if (pending == 0) then
                pending = i
                i = i + 1
            else
                ! Two real eigenvalues are one mode, s^2 + 2 delta s + omega^2 = 0: omega^2 =
                ! mu_1 mu_2 (a rigid-body double zero split by round-off into +-epsilon gives
                ! omega^2 = -epsilon^2), delta = (mu_1 + mu_2) / 2.
                call add_mode(sign(sqrt(abs(mu_re(i) * mu_re(pending))), mu_re(i) * &
                    mu_re(pending)), 0.5_rk * (mu_re(i) + mu_re(pending)), &
                    max(errors(i), errors(pending)), vec_re(:, pending), 0.0_rk * vec_re(:, i))
                pending = 0
                i = i + 1
            end if
        end do
        if (modes%n < n_modes) then
            why = 'SLEPc found ' // str(modes%n) // ' of the ' // str(n_modes) // ' modes asked ' // &
                'for (raise -modes_eps_max_it, or ask for fewer modes)'
            RS_SET_ERROR(err, 'eigen_solve', why)
        end if
    contains

        subroutine add_mode(omega, decay, residual, re, im)
            real(rk), intent(in) :: omega, decay, residual, re(:), im(:)
            real(rk) :: scale
            modes%n = modes%n + 1
            modes%omega(modes%n) = omega
            modes%decay(modes%n) = decay
            modes%residual(modes%n) = residual
            scale = sqrt(maxval(re**2 + im**2))
            if (scale <= 0.0_rk) scale = 1.0_rk
            modes%shape(:, modes%n) = re / scale
            modes%shape_im(:, modes%n) = im / scale
        end subroutine add_mode
    end subroutine eigen_solve

    !> rs_modes_solve on `pencil` equilibrated at the frequency `weight` (rs_system_
    !> linearization's equilibrate; solve_modes): D_r P D_c has P's eigenvalues, and its
    !> eigenvectors y give P's, x = D_c y. Arguments as rs_modes_solve's.
    subroutine equilibrated_solve(pencil, degree, n_wanted, shift, weight, n_found, mu_re, &
            mu_im, vec_re, vec_im, errors, text, message, ierr)
        type(pencil_t), intent(in) :: pencil
        integer, intent(in) :: degree, n_wanted
        real(rk), intent(in) :: shift, weight
        integer(c_int), intent(out) :: n_found, ierr
        real(rk), intent(out) :: mu_re(:), mu_im(:), vec_re(:, :), vec_im(:, :), errors(:)
        character(kind=c_char), intent(out) :: text(:), message(:)
        real(rk), allocatable :: row_scale(:), col_scale(:)
        type(pencil_t) :: scaled
        integer :: i
        allocate(row_scale(pencil%n), col_scale(pencil%n))
        call equilibrate(pencil, weight, row_scale, col_scale)
        scaled = pencil
        call scale_values(scaled%a0)
        call scale_values(scaled%a1)
        call scale_values(scaled%a2)
        ierr = rs_modes_solve(int(pencil%n, c_int), pencil%row_ptr, pencil%cols, scaled%a0, &
            scaled%a1, scaled%a2, int(degree, c_int), int(n_wanted, c_int), shift, n_found, &
            mu_re, mu_im, vec_re, vec_im, errors, text, int(size(text), c_int), message, &
            int(size(message), c_int))
        if (ierr /= 0) return
        do i = 1, n_found
            vec_re(:, i) = col_scale * vec_re(:, i)
            vec_im(:, i) = col_scale * vec_im(:, i)
        end do
    contains

        !> Values on the pencil's pattern scaled in place: D_r values D_c.
        pure subroutine scale_values(values)
            real(rk), intent(inout) :: values(:)
            integer :: row, k
            do row = 1, pencil%n
                do k = pencil%row_ptr(row) + 1, pencil%row_ptr(row + 1)
                    values(k) = row_scale(row) * values(k) * col_scale(pencil%cols(k) + 1)
                end do
            end do
        end subroutine scale_values
    end subroutine equilibrated_solve

    !> SLEPc's version ("3.18.2").
    function slepc_version() result(text)
        character(len=:), allocatable :: text
        character(kind=c_char) :: buffer(32)
        call rs_slepc_version(buffer, int(size(buffer), c_int))
        text = from_c_string(buffer)
    end function slepc_version

end module rs_solver_modal_solver
