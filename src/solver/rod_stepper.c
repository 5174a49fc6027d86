/* The rod stepper (interface and callback rules in include/rs_rod_stepper.h): one rodmid TS on
   PETSC_COMM_SELF per rod (DESIGN.md §5: each rod is solved with sequential objects, no
   communication in the time loop), driven from Fortran through bind(C).

   The functions called from Fortran return int and a message; the work is done in
   PetscErrorCode functions with PetscCall, and a PETSc error handler pushed around them keeps
   the first PETSc message so that it reaches the Fortran error object (STYLE.md item 11).

   Floating-point traps: Debug builds trap invalid, zero and overflow in rodsolve's Fortran
   (cmake/RodsolveFlags.cmake), and the trap mask is global. PETSc makes Inf on purpose (a
   domain error sets the residual to Inf, VecSetInf computes 1/0), which would kill a Debug
   run exactly when a step should be cut (DESIGN.md §3). So every entry point runs PETSc in
   non-stop mode (feholdexcept) and restores the caller's environment on return, and the
   callbacks run in the caller's environment: kernels keep their traps. */
#include <petscts.h>
#include <fenv.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "rs_rodmid.h"
#include "rs_rod_stepper.h"
#include "rs_rodchain.h"
#include "rs_petsc_error_capture.h"

typedef struct {
    TS             ts;
    Vec            X;      /* the TS state */
    Vec            X_prev; /* the state at the start of the substep, for the poststep callback */
    Mat            J;
    PetscInt       n_state, n_unknown;
    rs_cb_residual residual;
    rs_cb_jacobian jacobian;
    rs_cb_vec      predictor;
    rs_cb_update   update;
    rs_cb_poststep poststep;
    rs_cb_admissible admissible; /* the feasible-step filter's test, or NULL */
    int              order;      /* 2: a midpoint step per step; 4: Suzuki's composition */
    /* Error-controlled steps (traits->adaptive; docs/theory/time_integration.md), else unused:
       the accepted states before the current step's start, newest first, for the divided
       differences of the error estimate; the current step's start and its sub-steps' ends,
       booked (poststep) only once the step is accepted; the load kinks to hit. */
    int      adaptive;
    double   h_next;                 /* the controller's next step */
    Vec      past[4];                /* X at past_t, newest first; order of them in use */
    double   past_t[4];
    int      n_past;
    Vec      X_start;                /* the state at the start of the step being tried */
    double   t_start;
    Vec      sub_end[5];             /* the state after each sub-step of the step tried */
    double   sub_h[5], sub_fnorm[5];
    int      sub_its[5], n_sub;
    double  *breaks;                 /* sorted */
    int      n_breaks;
    int      rejected;               /* steps the error control rejected, over the run */
    int      max_failures;           /* Newton failures in a row before the run stops */
    double   h_smallest, h_largest;  /* accepted steps, over the run */
    void          *ctx;
    fenv_t         caller_env; /* floating-point environment of the Fortran caller */
    /* A system shared by all ranks (DESIGN.md §5: bundles on PETSC_COMM_WORLD): each rank owns
       the rows [unknown_lo, unknown_hi) and the state entries [state_lo, state_hi); the
       callbacks see the whole X_n and Y, gathered on every rank, and fill the owned rows. */
    int            distributed;
    MPI_Comm       comm;
    PetscInt       state_lo, state_hi, unknown_lo, unknown_hi;
    VecScatter     gather_state, gather_unknown;
    /* The gathers of the evaluations: only the entries this rank's rows read (its rods and
       their neighbours, rs_stepper_set_needed), or NULL: the whole system. */
    VecScatter     needed_state, needed_unknown;
    Vec            Y_layout;               /* a vector of Y's layout, for needed_unknown */
    Vec            x_all, x2_all, y_all;   /* sequential, whole length */
    PetscScalar   *f_all, *values_all, *out_all;
    PetscInt      *row_ptr_all, *cols_all; /* the whole CSR pattern (0-based) */
    /* Bordered solves (rs_stepper_factor, rs_stepper_solve): right-hand side and solution. */
    Vec            rhs, sol;
    PetscInt       nnz; /* entries of the pattern (one rank) */
} RsStepper;

/* Enter PETSc from the caller: remember its environment, switch traps off. */
static void enter_petsc(RsStepper *s)
{
    feholdexcept(&s->caller_env);
}

/* Back to the caller, with its traps and its flags (those PETSc raised are dropped). */
static void leave_petsc(const RsStepper *s)
{
    fesetenv(&s->caller_env);
}

/* A callback runs in the caller's environment; PETSc's is put back afterwards. */
static void enter_user(const RsStepper *s, fenv_t *petsc_env)
{
    fegetenv(petsc_env);
    fesetenv(&s->caller_env);
}

static void leave_user(const fenv_t *petsc_env)
{
    fesetenv(petsc_env);
}


static void set_message(char *errmsg, int errlen, const char *format, ...)
{
    va_list args;
    if (!errmsg || errlen <= 0) return;
    va_start(args, format);
    vsnprintf(errmsg, (size_t)errlen, format, args);
    va_end(args);
}

/* A PETSc error of `what` as the message: the caught PETSc text, else PETSc's generic one. */
static void set_petsc_message(char *errmsg, int errlen, const char *what, PetscErrorCode ierr,
                              const RsErrorCapture *capture)
{
    const char *generic = NULL;
    if (capture->have) {
        set_message(errmsg, errlen, "%s: %s", what, capture->text);
    } else {
        PetscErrorMessage(ierr, &generic, NULL);
        set_message(errmsg, errlen, "%s: PETSc error %d (%s)", what, (int)ierr,
                    generic ? generic : "unknown");
    }
}

/* ---- The step problem of rodmid, on raw arrays -------------------------------------------- */

/* Distributed mode: the whole of a distributed vector V on every rank, in `all`. */
static PetscErrorCode gather(VecScatter scatter, Vec V, Vec all)
{
    PetscFunctionBegin;
    PetscCall(VecScatterBegin(scatter, V, all, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(scatter, V, all, INSERT_VALUES, SCATTER_FORWARD));
    PetscFunctionReturn(0);
}

/* The gathers before an evaluation: the needed entries where set, else the whole system. */
static VecScatter state_gather(const RsStepper *s)
{
    return s->needed_state ? s->needed_state : s->gather_state;
}

static VecScatter unknown_gather(const RsStepper *s)
{
    return s->needed_unknown ? s->needed_unknown : s->gather_unknown;
}

/* Distributed mode: copy the owned part [lo, hi) of a whole-length array into V. */
static PetscErrorCode scatter_owned(const PetscScalar *whole, PetscInt lo, PetscInt hi, Vec V)
{
    PetscScalar *a;

    PetscFunctionBegin;
    PetscCall(VecGetArray(V, &a));
    PetscCall(PetscArraycpy(a, whole + lo, hi - lo));
    PetscCall(VecRestoreArray(V, &a));
    PetscFunctionReturn(0);
}

/* Distributed mode: a status every rank agrees on (the largest), so that a domain error seen
   by one rank cuts the step on all. */
static PetscErrorCode agree(const RsStepper *s, int *status)
{
    int local = *status;

    PetscFunctionBegin;
    PetscCallMPI(MPI_Allreduce(&local, status, 1, MPI_INT, MPI_MAX, s->comm));
    PetscFunctionReturn(0);
}

/* Distributed mode: call `callback` (the residual or the Jacobian one: the same signature) on
   the whole X_n and Y, gathered on every rank, writing the whole-length `out`; the status is
   agreed by all ranks. */
static PetscErrorCode call_gathered(RsStepper *s, rs_cb_residual callback, PetscReal t_n,
                                    PetscReal h, Vec X_n, Vec Y, PetscScalar *out, int *status)
{
    const PetscScalar *x, *y;
    fenv_t             env;

    PetscFunctionBegin;
    PetscCall(gather(state_gather(s), X_n, s->x_all));
    PetscCall(gather(unknown_gather(s), Y, s->y_all));
    PetscCall(VecGetArrayRead(s->x_all, &x));
    PetscCall(VecGetArrayRead(s->y_all, &y));
    enter_user(s, &env);
    *status = callback(s->ctx, t_n, h, x, y, out);
    leave_user(&env);
    PetscCall(VecRestoreArrayRead(s->y_all, &y));
    PetscCall(VecRestoreArrayRead(s->x_all, &x));
    PetscCall(agree(s, status));
    PetscFunctionReturn(0);
}

static PetscErrorCode step_residual_distributed(RsStepper *s, PetscReal t_n, PetscReal h, Vec X_n,
                                                Vec Y, Vec F, int *status)
{
    PetscFunctionBegin;
    PetscCall(call_gathered(s, s->residual, t_n, h, X_n, Y, s->f_all, status));
    PetscCall(scatter_owned(s->f_all, s->unknown_lo, s->unknown_hi, F));
    PetscFunctionReturn(0);
}

static PetscErrorCode step_jacobian_distributed(RsStepper *s, PetscReal t_n, PetscReal h, Vec X_n,
                                                Vec Y, Mat J, int *status)
{
    PetscFunctionBegin;
    PetscCall(call_gathered(s, s->jacobian, t_n, h, X_n, Y, s->values_all, status));
    /* The owned rows' values in the order of the pattern the matrix was preallocated from
       (MatMPIAIJSetPreallocationCSR, sorted columns): copied in place. Row by row through
       MatSetValues, which searches every column, the Jacobian took longer on 2 ranks than on
       1 (0.26 s against 0.19 s on the 37-wire strand, docs/performance.md). */
    PetscCall(MatUpdateMPIAIJWithArray(J, s->values_all + s->row_ptr_all[s->unknown_lo]));
    PetscFunctionReturn(0);
}

static PetscErrorCode step_residual(PetscReal t_n, PetscReal h, Vec X_n, Vec Y, Vec F, void *ctx)
{
    RsStepper         *s = (RsStepper *)ctx;
    const PetscScalar *x, *y;
    PetscScalar       *f;
    SNES               snes;
    int                status;
    fenv_t             env;

    PetscFunctionBegin;
    if (s->distributed) {
        PetscCall(step_residual_distributed(s, t_n, h, X_n, Y, F, &status));
    } else {
        PetscCall(VecGetArrayRead(X_n, &x));
        PetscCall(VecGetArrayRead(Y, &y));
        PetscCall(VecGetArray(F, &f));
        enter_user(s, &env);
        status = s->residual(s->ctx, t_n, h, x, y, f);
        leave_user(&env);
        PetscCall(VecRestoreArray(F, &f));
        PetscCall(VecRestoreArrayRead(Y, &y));
        PetscCall(VecRestoreArrayRead(X_n, &x));
    }
    if (status == 1) {
        /* DESIGN.md §3: an invalid state cuts the step, not the run. */
        PetscCall(TSGetSNES(s->ts, &snes));
        PetscCall(SNESSetFunctionDomainError(snes));
    } else {
        PetscCheck(status == 0, PETSC_COMM_SELF, PETSC_ERR_USER,
                   "the residual callback failed with status %d at t = %g, h = %g", status,
                   (double)t_n, (double)h);
    }
    PetscFunctionReturn(0);
}

static PetscErrorCode step_jacobian(PetscReal t_n, PetscReal h, Vec X_n, Vec Y, Mat J, void *ctx)
{
    RsStepper         *s = (RsStepper *)ctx;
    const PetscScalar *x, *y;
    PetscScalar       *values;
    SNES               snes;
    int                status;
    fenv_t             env;

    PetscFunctionBegin;
    /* The values of an AIJ matrix are stored row by row with sorted columns, i.e. in the order
       of the CSR pattern it was preallocated from: the callback writes them in place. The
       pattern never changes, so the factorization's symbolic phase is not redone (§3). */
    if (s->distributed) {
        PetscCall(step_jacobian_distributed(s, t_n, h, X_n, Y, J, &status));
    } else {
        PetscCall(VecGetArrayRead(X_n, &x));
        PetscCall(VecGetArrayRead(Y, &y));
        PetscCall(MatSeqAIJGetArray(J, &values));
        enter_user(s, &env);
        status = s->jacobian(s->ctx, t_n, h, x, y, values);
        leave_user(&env);
        PetscCall(MatSeqAIJRestoreArray(J, &values));
        PetscCall(VecRestoreArrayRead(Y, &y));
        PetscCall(VecRestoreArrayRead(X_n, &x));
    }
    PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
    if (status == 1) {
        PetscCall(TSGetSNES(s->ts, &snes));
        PetscCall(SNESSetJacobianDomainError(snes));
    } else {
        PetscCheck(status == 0, PETSC_COMM_SELF, PETSC_ERR_USER,
                   "the Jacobian callback failed with status %d at t = %g, h = %g", status,
                   (double)t_n, (double)h);
    }
    PetscFunctionReturn(0);
}

/* The feasible-step filter's test (rs_stepper_set_admissible): on a shared system each rank
   asks its own part, on the gathered X_n and Y, and the ranks agree. */
static PetscErrorCode step_admissible(PetscReal t_n, PetscReal h, Vec X_n, Vec Y, PetscBool *ok,
                                      void *ctx)
{
    RsStepper         *s      = (RsStepper *)ctx;
    Vec                x_from = X_n, y_from = Y;
    const PetscScalar *x, *y;
    int                status;
    fenv_t             env;

    PetscFunctionBegin;
    if (s->distributed) {
        PetscCall(gather(state_gather(s), X_n, s->x_all));
        PetscCall(gather(unknown_gather(s), Y, s->y_all));
        x_from = s->x_all;
        y_from = s->y_all;
    }
    PetscCall(VecGetArrayRead(x_from, &x));
    PetscCall(VecGetArrayRead(y_from, &y));
    enter_user(s, &env);
    status = s->admissible(s->ctx, t_n, h, x, y);
    leave_user(&env);
    PetscCall(VecRestoreArrayRead(y_from, &y));
    PetscCall(VecRestoreArrayRead(x_from, &x));
    if (s->distributed) PetscCall(agree(s, &status));
    *ok = status == 0 ? PETSC_TRUE : PETSC_FALSE;
    PetscFunctionReturn(0);
}

static PetscErrorCode step_predictor(PetscReal t_n, PetscReal h, Vec X_n, Vec Y, void *ctx)
{
    RsStepper         *s = (RsStepper *)ctx;
    const PetscScalar *x;
    PetscScalar       *y;
    int                status;
    fenv_t             env;

    PetscFunctionBegin;
    if (s->distributed) {
        PetscCall(gather(state_gather(s), X_n, s->x_all));
        PetscCall(VecGetArrayRead(s->x_all, &x));
        enter_user(s, &env);
        status = s->predictor(s->ctx, t_n, h, x, s->out_all);
        leave_user(&env);
        PetscCall(VecRestoreArrayRead(s->x_all, &x));
        PetscCall(scatter_owned(s->out_all, s->unknown_lo, s->unknown_hi, Y));
    } else {
        PetscCall(VecGetArrayRead(X_n, &x));
        PetscCall(VecGetArray(Y, &y));
        enter_user(s, &env);
        status = s->predictor(s->ctx, t_n, h, x, y);
        leave_user(&env);
        PetscCall(VecRestoreArray(Y, &y));
        PetscCall(VecRestoreArrayRead(X_n, &x));
    }
    PetscCheck(status == 0, PETSC_COMM_SELF, PETSC_ERR_USER,
               "the predictor callback failed with status %d at t = %g, h = %g", status,
               (double)t_n, (double)h);
    PetscFunctionReturn(0);
}

static PetscErrorCode step_update(PetscReal t_n, PetscReal h, Vec X_n, Vec Y, Vec X_np1, void *ctx)
{
    RsStepper         *s = (RsStepper *)ctx;
    const PetscScalar *x, *y;
    PetscScalar       *x1;
    int                status;
    fenv_t             env;

    PetscFunctionBegin;
    if (s->distributed) {
        PetscCall(gather(state_gather(s), X_n, s->x_all));
        PetscCall(gather(unknown_gather(s), Y, s->y_all));
        PetscCall(VecGetArrayRead(s->x_all, &x));
        PetscCall(VecGetArrayRead(s->y_all, &y));
        enter_user(s, &env);
        status = s->update(s->ctx, t_n, h, x, y, s->out_all);
        leave_user(&env);
        PetscCall(VecRestoreArrayRead(s->y_all, &y));
        PetscCall(VecRestoreArrayRead(s->x_all, &x));
        PetscCall(scatter_owned(s->out_all, s->state_lo, s->state_hi, X_np1));
    } else {
        PetscCall(VecGetArrayRead(X_n, &x));
        PetscCall(VecGetArrayRead(Y, &y));
        PetscCall(VecGetArray(X_np1, &x1));
        enter_user(s, &env);
        status = s->update(s->ctx, t_n, h, x, y, x1);
        leave_user(&env);
        PetscCall(VecRestoreArray(X_np1, &x1));
        PetscCall(VecRestoreArrayRead(Y, &y));
        PetscCall(VecRestoreArrayRead(X_n, &x));
    }
    PetscCheck(status == 0, PETSC_COMM_SELF, PETSC_ERR_USER,
               "the update callback failed with status %d at t = %g, h = %g", status, (double)t_n,
               (double)h);
    PetscFunctionReturn(0);
}

/* ---- Create --------------------------------------------------------------------------------- */

/* Problems of the arguments, as a message; 0 if none. */
static int check_arguments(int n_state, int n_unknown, const int *row_ptr, const int *cols,
                           rs_cb_residual residual, rs_cb_jacobian jacobian, rs_cb_vec predictor,
                           rs_cb_update update, const struct rs_stepper_traits *traits,
                           char *errmsg, int errlen)
{
    if (n_state < 1 || n_unknown < 1) {
        set_message(errmsg, errlen, "rod stepper: n_state = %d and n_unknown = %d must be >= 1",
                    n_state, n_unknown);
        return 1;
    }
    if (!residual || !jacobian) {
        set_message(errmsg, errlen,
                    "rod stepper: the residual and Jacobian callbacks are required");
        return 1;
    }
    if (n_unknown != n_state && (!predictor || !update)) {
        set_message(
            errmsg, errlen,
            "rod stepper: n_unknown = %d differs from n_state = %d, so a predictor and an update "
            "callback are required (the defaults copy X into Y and back)",
            n_unknown, n_state);
        return 1;
    }
    if (!traits) {
        set_message(errmsg, errlen, "rod stepper: no traits (Newton settings, solver flags)");
        return 1;
    }
    if (traits->order != 2 && traits->order != 4) {
        set_message(errmsg, errlen, "rod stepper: order %d; allowed: 2 (midpoint) or 4 (the "
                    "five-stage composition of midpoint steps)", traits->order);
        return 1;
    }
    if (traits->adaptive &&
        !(traits->rtol >= 0.0 && traits->atol >= 0.0 && traits->rtol + traits->atol > 0.0 &&
          traits->dt_min > 0.0 && traits->dt_min <= traits->dt_initial &&
          traits->dt_initial <= traits->dt_max)) {
        set_message(errmsg, errlen, "rod stepper: adaptive steps need rtol, atol >= 0 (not both "
                    "0) and 0 < dt_min <= dt_initial <= dt_max; got rtol %g, atol %g, dt_min %g, "
                    "dt_initial %g, dt_max %g", traits->rtol, traits->atol, traits->dt_min,
                    traits->dt_initial, traits->dt_max);
        return 1;
    }
    if (!(traits->newton_atol >= 0.0) || !(traits->newton_rtol >= 0.0) ||
        traits->max_newton < 0 || traits->max_cutbacks < 0) {
        set_message(
            errmsg, errlen,
            "rod stepper: newton_atol = %g and newton_rtol = %g must be >= 0, max_newton = %d and "
            "max_cutbacks = %d >= 0",
            traits->newton_atol, traits->newton_rtol, traits->max_newton, traits->max_cutbacks);
        return 1;
    }
    if (!row_ptr || !cols || row_ptr[0] != 0) {
        set_message(errmsg, errlen,
                    "rod stepper: the CSR pattern must be given, 0-based (row_ptr[0] = 0)");
        return 1;
    }
    for (int i = 0; i < n_unknown; ++i) {
        if (row_ptr[i + 1] < row_ptr[i]) {
            set_message(errmsg, errlen, "rod stepper: row_ptr decreases at row %d (0-based)", i);
            return 1;
        }
        for (int k = row_ptr[i]; k < row_ptr[i + 1]; ++k) {
            if (cols[k] < 0 || cols[k] >= n_unknown) {
                set_message(errmsg, errlen,
                            "rod stepper: column %d of row %d (0-based) is outside 0..%d", cols[k],
                            i, n_unknown - 1);
                return 1;
            }
            if (k > row_ptr[i] && cols[k] <= cols[k - 1]) {
                /* AIJ stores sorted columns: any other order would scramble the values. */
                set_message(errmsg, errlen,
                            "rod stepper: the columns of row %d (0-based) are not strictly "
                            "increasing (%d after %d)",
                            i, cols[k], cols[k - 1]);
                return 1;
            }
        }
    }
    return 0;
}

/* Distributed mode: X and Y split by the owned ranges, the Jacobian's owned rows preallocated
   from the whole pattern, the gathers and the whole-length work arrays of the callbacks. */
static PetscErrorCode distributed_setup(RsStepper *s, const int *row_ptr, const int *cols,
                                        Vec *Y_template)
{
    const PetscInt n_rows = s->unknown_hi - s->unknown_lo, nnz = row_ptr[s->n_unknown];
    PetscInt      *local_ptr;

    PetscFunctionBegin;
    PetscCall(VecCreateMPI(s->comm, s->state_hi - s->state_lo, s->n_state, &s->X));
    PetscCall(VecCreateMPI(s->comm, n_rows, s->n_unknown, Y_template));
    PetscCall(VecScatterCreateToAll(s->X, &s->gather_state, &s->x_all));
    PetscCall(VecDuplicate(s->x_all, &s->x2_all));
    PetscCall(VecScatterCreateToAll(*Y_template, &s->gather_unknown, &s->y_all));
    PetscCall(PetscObjectReference((PetscObject)*Y_template));
    s->Y_layout = *Y_template;
    PetscCall(PetscMalloc1(s->n_unknown + 1, &s->row_ptr_all));
    PetscCall(PetscMalloc1(nnz, &s->cols_all));
    for (PetscInt i = 0; i <= s->n_unknown; ++i) s->row_ptr_all[i] = row_ptr[i];
    for (PetscInt k = 0; k < nnz; ++k) s->cols_all[k] = cols[k];
    PetscCall(PetscCalloc1(s->n_unknown, &s->f_all));
    PetscCall(PetscCalloc1(nnz > 0 ? nnz : 1, &s->values_all));
    PetscCall(PetscCalloc1(s->n_state > s->n_unknown ? s->n_state : s->n_unknown, &s->out_all));

    PetscCall(PetscMalloc1(n_rows + 1, &local_ptr));
    for (PetscInt i = 0; i <= n_rows; ++i)
        local_ptr[i] = row_ptr[s->unknown_lo + i] - row_ptr[s->unknown_lo];
    PetscCall(MatCreate(s->comm, &s->J));
    PetscCall(MatSetSizes(s->J, n_rows, n_rows, s->n_unknown, s->n_unknown));
    PetscCall(MatSetType(s->J, MATMPIAIJ));
    PetscCall(MatMPIAIJSetPreallocationCSR(s->J, local_ptr,
                                           s->cols_all + row_ptr[s->unknown_lo], NULL));
    PetscCall(PetscFree(local_ptr));
    PetscFunctionReturn(0);
}

/* ---- The local error of an adaptive step (docs/theory/time_integration.md) ----------------

   A step of order p has the local error C h^(p+1) x^(p+1) (the midpoint rule: C = 1/12, for
   x' = lambda x: (1 + z/2)/(1 - z/2) - e^z = z^3/12 + ...; Suzuki's composition of it:
   C = 9.297e-4, the z^5 coefficient of its stability function less 1/120). x^(p+1)/(p+1)! is
   the divided difference of the last p + 2 accepted states (variable steps), so
   LTE = C (p+1)! h^(p+1) x[t_(n+1-p-1), ..., t_(n+1)] - Milne's device with the polynomial
   extrapolation of the past states as the predictor; no extra solve. TSErrorWeightedNorm weighs
   it with the TS's atol and rtol (RMS over the state). */
#define LTE_CONSTANT_MIDPOINT (1.0 / 12.0)
#define LTE_CONSTANT_SUZUKI 9.296999424540427e-4

static PetscErrorCode estimate_local_error(TS ts, NormType type, PetscInt *order, PetscReal *wlte,
                                           void *ctx)
{
    RsStepper  *s = (RsStepper *)ctx;
    const int   p = s->order, n = p + 2;
    Vec         points[6];
    PetscScalar weights[6];
    PetscReal   times[6], h, scale, absolute, relative;
    Vec         estimate = s->X_prev; /* free between steps */

    PetscFunctionBegin;
    *wlte  = -1.0;
    *order = p + 1;
    if (s->n_past < p) PetscFunctionReturn(0); /* after a start or a kink: no estimate yet */
    for (int k = 0; k < p; ++k) {
        points[k] = s->past[p - 1 - k];
        times[k]  = s->past_t[p - 1 - k];
    }
    points[p]     = s->X_start;
    times[p]      = s->t_start;
    points[p + 1] = s->X;
    PetscCall(TSGetTime(ts, &times[p + 1]));
    h     = times[p + 1] - times[p];
    scale = (p == 4 ? LTE_CONSTANT_SUZUKI * 120.0 : LTE_CONSTANT_MIDPOINT * 6.0) * PetscPowReal(h, p + 1);
    for (int j = 0; j < n; ++j) {
        PetscReal w = 1.0;
        for (int k = 0; k < n; ++k)
            if (k != j) w *= times[j] - times[k];
        weights[j] = scale / w;
    }
    PetscCall(VecCopy(s->X, estimate));
    PetscCall(VecMAXPY(estimate, n, weights, points));
    PetscCall(TSErrorWeightedNorm(ts, s->X, estimate, type, wlte, &absolute, &relative));
    /* Per step, not per unit step: a tolerance tol h / t_span shrinks with h below the
       residual Newton leaves, and the steps collapsed to dt_min on the flying spaghetti. */
    PetscFunctionReturn(0);
}

static PetscErrorCode stepper_setup(RsStepper *s, const int *row_ptr, const int *cols,
                                    const struct rs_stepper_traits *traits, int n_blocks,
                                    const int *block_lengths)
{
    char      defaults[1024], mumps[160], linear[512], message[1024];
    Vec       Y_template = NULL;
    SNES           snes;
    SNESLineSearch line_search;
    KSP       ksp;
    PC        pc;
    PetscBool is_rodmid;
    TSType    type;

    PetscFunctionBegin;
    PetscCall(rs_rodmid_register());
    PetscCall(rs_rodchain_register());

    /* Scene values as the bottom layer of the options (DESIGN.md §3): newtonls with the bt line
       search, the absolute Newton test of the method documents with PETSc's relative tests
       off unless the scene asks, and LU (the package is set below, per system). */
    /* A step problem affine in Y (seed 004) is one linear solve: SNES KSPONLY, no Newton loop. */
    /* MUMPS for bundles (docs/performance.md, "Bundles"): AMD needs 2 to 4 times fewer flops
       than the automatic choice (PORD: Debian's MUMPS has neither METIS nor SCOTCH). A shared
       system gives MUMPS a distributed matrix, for which MUMPS does not permute large entries
       onto the diagonal (ICNTL(6) needs centralized input): the zero diagonal of the
       multiplier rows delays thousands of pivots, which overruns a 50% work-space margin (a
       400% margin holds), and a relative pivot threshold of 1e-4 instead of 1e-2 halves the
       delayed pivots and the flops with the same Newton iterations; the root node is
       factored without ScaLAPACK (ICNTL(13) = 1), faster on a loaded machine.
       Single rods use AMD too: MUMPS's automatic choice (PORD) makes the factorization of a
       long chain superlinear (3.3 and 3.8 us per unknown at n_e = 256 and 1024 against 2.4 and
       2.6 with AMD). The column permutation stays MUMPS's choice (the maximum transversal,
       MC64): its analysis grows faster than the chain (ph_director: 0.76 s at n_e = 1024,
       19.5 s at 4096, once per run), and without it (ICNTL(6) = 0: 0.09 and 0.38 s) the stiff
       tube of seed 004 on 16 elements fails its first step (DIVERGED_LINEAR_SOLVE); see
       docs/performance.md, "ph_director: cost per step". */
    if (s->distributed)
        snprintf(mumps, sizeof(mumps), "-mat_mumps_icntl_14 400 -mat_mumps_icntl_7 0 "
                                       "-mat_mumps_cntl_1 1e-4 -mat_mumps_icntl_13 1");
    else
        snprintf(mumps, sizeof(mumps), "-mat_mumps_icntl_14 50 -mat_mumps_icntl_7 0 "
                                       "-mat_mumps_cntl_1 0.01 -mat_mumps_icntl_13 0");
    /* The linear solver: LU of the whole Jacobian, or, for a system given in blocks (one per
       rod with the coupling unknowns it owns; docs/performance.md, "Bundles: block Jacobi"),
       GMRES preconditioned by the exact chain LU of every rod's block (PCBJACOBI; rodchain
       finds the chain of a rod bordered by its plate-tie multipliers in a breadth-first order,
       1.7 times faster per Newton iteration than sequential MUMPS on the blocks of the 19-wire
       strand), the couplings between the rods (contact) left to the Krylov iterations.
       Preconditioned on the right, so that GMRES tests the true residual: its absolute
       tolerance is a tenth of newton_atol, below what Newton accepts, so Newton stops where it
       stopped with LU (the energy and the tie rows hold as before); the relative test is off
       (1e-12). (On the left GMRES tests the preconditioned residual, 1e7 times the true one on
       the strands: 1.3 to 1.6 times the iterations for nothing.) MUMPS takes a block the chain
       LU cannot factor (its fallback, with AMD). */
    if (n_blocks > 1)
        snprintf(linear, sizeof(linear),
                 "-ksp_type gmres -ksp_pc_side right -ksp_gmres_restart 100 -ksp_max_it 500 "
                 "-ksp_rtol 1e-12 -ksp_atol %.17g -pc_type bjacobi -sub_ksp_type preonly "
                 "-sub_pc_type lu -sub_pc_factor_mat_solver_type rodchain "
                 "-sub_mat_mumps_icntl_7 0",
                 0.1 * traits->newton_atol);
    else
        snprintf(linear, sizeof(linear), "-ksp_type preonly -pc_type lu");
    snprintf(defaults, sizeof(defaults),
             "-snes_type %s -snes_atol %.17g -snes_rtol %.17g "
             "-snes_stol 0 -snes_max_it %d %s %s "
             "-ts_rodmid_max_cutbacks %d -ts_rodmid_reuse_jacobian %.17g%s",
             traits->linear_step ? "ksponly" : "newtonls", traits->newton_atol,
             traits->newton_rtol, traits->max_newton, linear, mumps,
             traits->adaptive ? 0 : traits->max_cutbacks, /* adaptive: the controller cuts */
             traits->linear_step ? 0.0 : traits->jacobian_reuse,
             /* adaptive: every controlled entry's local error within atol + rtol |x| */
             traits->adaptive ? " -ts_adapt_wnormtype infinity -ts_adapt_dsp_filter H211PI" : "");
    PetscCheck(rs_petsc_apply_options(defaults, NULL, message, (int)sizeof(message)) == 0,
               PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", message);

    if (s->distributed) {
        PetscCall(distributed_setup(s, row_ptr, cols, &Y_template));
    } else {
        PetscCall(VecCreateSeq(PETSC_COMM_SELF, s->n_state, &s->X));
        PetscCall(MatCreate(PETSC_COMM_SELF, &s->J));
        PetscCall(MatSetSizes(s->J, s->n_unknown, s->n_unknown, s->n_unknown, s->n_unknown));
        PetscCall(MatSetType(s->J, MATSEQAIJ));
        PetscCall(MatSeqAIJSetPreallocationCSR(s->J, (const PetscInt *)row_ptr,
                                               (const PetscInt *)cols, NULL));
        s->nnz = row_ptr[s->n_unknown];
        if (s->n_unknown != s->n_state)
            PetscCall(VecCreateSeq(PETSC_COMM_SELF, s->n_unknown, &Y_template));
    }
    PetscCall(VecDuplicate(s->X, &s->X_prev));
    if (traits->adaptive) {
        for (int k = 0; k < s->order; ++k) PetscCall(VecDuplicate(s->X, &s->past[k]));
        for (int k = 0; k < (s->order == 4 ? 5 : 1); ++k)
            PetscCall(VecDuplicate(s->X, &s->sub_end[k]));
        PetscCall(VecDuplicate(s->X, &s->X_start));
    }
    PetscCall(MatSetOption(s->J, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));

    PetscCall(TSCreate(s->comm, &s->ts));
    PetscCall(TSSetType(s->ts, TSRODMID));
    PetscCall(TSSetProblemType(s->ts, TS_NONLINEAR));
    PetscCall(TSSetSolution(s->ts, s->X));
    PetscCall(TSRodmidSetStepProblem(s->ts, Y_template, s->J, step_residual, step_jacobian,
                                     s->predictor ? step_predictor : NULL,
                                     s->update ? step_update : NULL, s));
    PetscCall(VecDestroy(&Y_template));
    /* A diverged step is a result the stepper acts on (STYLE.md item 11), never an abort. */
    PetscCall(TSSetErrorIfStepFails(s->ts, PETSC_FALSE));
    PetscCall(TSSetExactFinalTime(s->ts, TS_EXACTFINALTIME_STEPOVER));
    if (traits->adaptive) {
        /* PETSc's controller on rodmid's error estimate: TSADAPTDSP, Söderlind's digital
           filter H211PI (a PI controller that smooths the step sequence). Measured on the
           flying spaghetti at rtol 1e-5: basic (the step factor 0.9 wlte^(-1/order)) rejected
           1,023 of 4,089 steps and took 2.0 s; dsp with its default filter 255 of 2,774, 1.4 s;
           H211PI none of 2,103, 1.1 s. -ts_adapt_type and -ts_adapt_dsp_filter override. */
        TSAdapt adapt;
        PetscCall(TSSetTolerances(s->ts, traits->atol, NULL, traits->rtol, NULL));
        PetscCall(TSGetAdapt(s->ts, &adapt));
        PetscCall(TSAdaptSetType(adapt, TSADAPTDSP));
        PetscCall(TSAdaptSetStepLimits(adapt, traits->dt_min, traits->dt_max));
        PetscCall(TSRodmidSetErrorEstimate(s->ts, estimate_local_error, s));
    }

    /* Programmatic settings before TSSetFromOptions, so that options still override them. */
    PetscCall(TSGetSNES(s->ts, &snes));
    PetscCall(SNESSetErrorIfNotConverged(snes, PETSC_FALSE));
    /* Only debug builds of PETSc look at a Jacobian domain error by default. */
    PetscCall(SNESSetCheckJacobianDomainError(snes, PETSC_TRUE));
    /* The LU package (DESIGN.md §3): for one rod the chain LU (rodchain, include/rs_rodchain.h:
       the rod's block-tridiagonal structure on dense LAPACK kernels, with partial pivoting
       for the saddle-point rows, MUMPS behind it where a panel is singular on its own); PETSc's
       own LU where the formulation says its Jacobian needs no pivoting (small nodal blocks:
       ph_planar and se3_strand, where it is faster than the chain's dense kernels,
       docs/performance.md); MUMPS for a system shared by the ranks.
       -pc_factor_mat_solver_type overrides any of them. */
    PetscCall(SNESGetKSP(snes, &ksp));
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PCSetType(pc, PCLU));
    PetscCall(PCFactorSetMatSolverType(pc, s->distributed ? MATSOLVERMUMPS
                                           : traits->native_lu ? MATSOLVERPETSC
                                                               : MATSOLVERRODCHAIN));
    /* The blocks of block Jacobi: given here (not an option), used if the options keep
       -pc_type bjacobi. */
    if (n_blocks > 1) {
        PetscInt *lengths;
        PetscCall(PetscMalloc1(n_blocks, &lengths));
        for (int b = 0; b < n_blocks; ++b) lengths[b] = block_lengths[b];
        PetscCall(PCSetType(pc, PCBJACOBI));
        PetscCall(PCBJacobiSetTotalBlocks(pc, n_blocks, lengths));
        PetscCall(PetscFree(lengths));
    }
    /* banded_unknowns: the formulation numbered its unknowns for a narrow band (se3_strand's
       block-tridiagonal interleaving), which the natural ordering keeps: no fill at all, and
       0.6 to 0.9 of the time of nested dissection (docs/performance.md). */
    if (traits->native_lu)
        PetscCall(PCFactorSetMatOrderingType(pc, traits->banded_unknowns ? MATORDERINGNATURAL
                                                                         : MATORDERINGND));
    /* The line search: backtracking (bt), or the full Newton step where the formulation's
       method document says Newton is run undamped (seed 001's schemes: the bt search cuts the
       first steps of the displacement schemes and multiplies their iterations,
       docs/performance.md). -snes_linesearch_type overrides either. */
    PetscCall(SNESGetLineSearch(snes, &line_search));
    PetscCall(SNESLineSearchSetType(line_search, traits->full_newton ? SNESLINESEARCHBASIC
                                                                     : SNESLINESEARCHBT));
    /* An undamped first step may raise a badly scaled residual (forces and moments of a
       slender rod) far above the start before Newton converges: no divergence test then. */
    if (traits->full_newton) PetscCall(SNESSetDivergenceTolerance(snes, -1.0));
    PetscCall(TSSetFromOptions(s->ts));
    PetscCall(PetscObjectTypeCompare((PetscObject)s->ts, TSRODMID, &is_rodmid));
    PetscCall(TSGetType(s->ts, &type));
    PetscCheck(is_rodmid, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
               "the rod stepper is a TS of type rodmid; remove -ts_type %s from the options", type);
    PetscCall(TSSetUp(s->ts));
    PetscFunctionReturn(0);
}

static void stepper_free(RsStepper *s)
{
    /* Errors of destruction are only reported (by PETSc's handler): nothing to act on. */
    enter_petsc(s);
    TSDestroy(&s->ts);
    MatDestroy(&s->J);
    VecDestroy(&s->X_prev);
    VecDestroy(&s->X);
    for (int k = 0; k < 4; ++k) VecDestroy(&s->past[k]);
    for (int k = 0; k < 5; ++k) VecDestroy(&s->sub_end[k]);
    VecDestroy(&s->X_start);
    free(s->breaks);
    VecScatterDestroy(&s->gather_state);
    VecScatterDestroy(&s->gather_unknown);
    VecScatterDestroy(&s->needed_state);
    VecScatterDestroy(&s->needed_unknown);
    VecDestroy(&s->Y_layout);
    VecDestroy(&s->x_all);
    VecDestroy(&s->x2_all);
    VecDestroy(&s->y_all);
    PetscFree(s->f_all);
    PetscFree(s->values_all);
    PetscFree(s->out_all);
    PetscFree(s->row_ptr_all);
    PetscFree(s->cols_all);
    VecDestroy(&s->rhs);
    VecDestroy(&s->sol);
    leave_petsc(s);
    free(s);
}

int rs_stepper_create(void **handle, int n_state, int n_unknown, const int *row_ptr,
                      const int *cols, rs_cb_residual residual, rs_cb_jacobian jacobian,
                      rs_cb_vec predictor, rs_cb_update update, rs_cb_poststep poststep, void *ctx,
                      const struct rs_stepper_traits *traits, const int *owned, int n_blocks,
                      const int *block_lengths, char *errmsg, int errlen)
{
    RsErrorCapture capture = {"", 0};
    RsStepper     *s;
    PetscErrorCode ierr;

    if (errmsg && errlen > 0) errmsg[0] = '\0';
    if (!handle) {
        set_message(errmsg, errlen, "rod stepper: no handle to create");
        return RS_STEPPER_BAD_ARGUMENT;
    }
    *handle = NULL;
    if (check_arguments(n_state, n_unknown, row_ptr, cols, residual, jacobian, predictor, update,
                        traits, errmsg, errlen))
        return RS_STEPPER_BAD_ARGUMENT;
    s = calloc(1, sizeof(*s));
    if (!s) {
        set_message(errmsg, errlen, "rod stepper: out of memory");
        return RS_STEPPER_BAD_ARGUMENT;
    }
    s->n_state   = n_state;
    s->n_unknown = n_unknown;
    s->residual  = residual;
    s->jacobian  = jacobian;
    s->predictor = predictor;
    s->update    = update;
    s->poststep  = poststep;
    s->order     = traits->order;
    s->adaptive  = traits->adaptive;
    s->h_next    = traits->dt_initial;
    s->max_failures = traits->max_cutbacks;
    s->ctx       = ctx;
    s->comm      = PETSC_COMM_SELF;
    if (owned) {
        s->distributed = 1;
        s->comm        = PETSC_COMM_WORLD;
        s->state_lo    = owned[0];
        s->state_hi    = owned[1];
        s->unknown_lo  = owned[2];
        s->unknown_hi  = owned[3];
    }

    enter_petsc(s);
    PetscPushErrorHandler(rs_capture_petsc_error, &capture);
    ierr = stepper_setup(s, row_ptr, cols, traits, block_lengths ? n_blocks : 0, block_lengths);
    PetscPopErrorHandler();
    leave_petsc(s);
    if (ierr) {
        set_petsc_message(errmsg, errlen, "rod stepper: creation failed", ierr, &capture);
        stepper_free(s);
        return (int)ierr;
    }
    *handle = s;
    return 0;
}

/* A gather of the entries `entries` (0-based, n of them) of V into the same places of the
   whole-length sequential `all`. */
static PetscErrorCode needed_gather(Vec V, Vec all, int n, const int *entries, VecScatter *scatter)
{
    IS is;

    PetscFunctionBegin;
    PetscCall(ISCreateGeneral(PETSC_COMM_SELF, n, entries, PETSC_COPY_VALUES, &is));
    PetscCall(VecScatterCreate(V, is, all, is, scatter));
    PetscCall(ISDestroy(&is));
    PetscFunctionReturn(0);
}

static PetscErrorCode stepper_set_needed(RsStepper *s, int n_state, const int *state_entries,
                                         int n_unknown, const int *unknown_entries)
{
    PetscFunctionBegin;
    PetscCall(VecScatterDestroy(&s->needed_state));
    PetscCall(VecScatterDestroy(&s->needed_unknown));
    PetscCall(needed_gather(s->X, s->x_all, n_state, state_entries, &s->needed_state));
    PetscCall(needed_gather(s->Y_layout, s->y_all, n_unknown, unknown_entries,
                            &s->needed_unknown));
    PetscFunctionReturn(0);
}

int rs_stepper_set_needed(void *handle, int n_state, const int *state_entries, int n_unknown,
                          const int *unknown_entries, char *errmsg, int errlen)
{
    RsErrorCapture capture = {"", 0};
    RsStepper     *s       = (RsStepper *)handle;
    PetscErrorCode ierr;

    if (errmsg && errlen > 0) errmsg[0] = '\0';
    if (!s || n_state < 0 || n_unknown < 0 || (n_state > 0 && !state_entries) ||
        (n_unknown > 0 && !unknown_entries)) {
        set_message(errmsg, errlen, "rod stepper: bad arguments to rs_stepper_set_needed");
        return RS_STEPPER_BAD_ARGUMENT;
    }
    for (int k = 0; k < n_state; ++k)
        if (state_entries[k] < 0 || state_entries[k] >= s->n_state) {
            set_message(errmsg, errlen, "rod stepper: needed state entry %d outside [0, %d)",
                        state_entries[k], (int)s->n_state);
            return RS_STEPPER_BAD_ARGUMENT;
        }
    for (int k = 0; k < n_unknown; ++k)
        if (unknown_entries[k] < 0 || unknown_entries[k] >= s->n_unknown) {
            set_message(errmsg, errlen, "rod stepper: needed unknown %d outside [0, %d)",
                        unknown_entries[k], (int)s->n_unknown);
            return RS_STEPPER_BAD_ARGUMENT;
        }
    if (!s->distributed) return 0;
    enter_petsc(s);
    PetscPushErrorHandler(rs_capture_petsc_error, &capture);
    ierr = stepper_set_needed(s, n_state, state_entries, n_unknown, unknown_entries);
    PetscPopErrorHandler();
    leave_petsc(s);
    if (ierr) {
        set_petsc_message(errmsg, errlen, "rod stepper: the gathers could not be set up", ierr,
                          &capture);
        return (int)ierr;
    }
    return 0;
}

/* ---- Advance -------------------------------------------------------------------------------- */

typedef struct {
    int         substeps, cutbacks, newton_its;
    double      fnorm;
    int         diverged;   /* Newton failed after all cut-backs */
    double      t_failed;   /* start of the failing substep: the time of the state left in x */
    double      h_smallest; /* the last step tried there */
    int         halvings;   /* cut-backs tried there */
    double      cut_factor; /* each by this factor: 1/2 with fixed steps, TSAdapt's
                               scale_solve_failed with adaptive ones */
    const char *snes_reason;
} RsAdvanceResult;

/* The poststep callback on an accepted (sub-)step from `before` at t0 to `after`: the
   formulation books its energy, work and histories. */
static PetscErrorCode book_step(RsStepper *s, PetscReal t0, PetscReal h, Vec before, Vec after,
                                PetscInt its, PetscReal fnorm)
{
    const PetscScalar *x0, *x1;
    int                status;
    fenv_t             env;

    PetscFunctionBegin;
    if (!s->poststep) PetscFunctionReturn(0);
    if (s->distributed) {
        /* The whole states on every rank. */
        PetscCall(gather(s->gather_state, before, s->x_all));
        PetscCall(gather(s->gather_state, after, s->x2_all));
        before = s->x_all;
        after  = s->x2_all;
    }
    PetscCall(VecGetArrayRead(before, &x0));
    PetscCall(VecGetArrayRead(after, &x1));
    enter_user(s, &env);
    status = s->poststep(s->ctx, t0, h, x0, x1, (int)its, fnorm);
    leave_user(&env);
    PetscCall(VecRestoreArrayRead(after, &x1));
    PetscCall(VecRestoreArrayRead(before, &x0));
    PetscCheck(status == 0, PETSC_COMM_SELF, PETSC_ERR_USER,
               "the poststep callback failed with status %d at t = %g, h = %g", status, t0, h);
    PetscFunctionReturn(0);
}

/* The step's span `span` (negative for the composition's middle sub-step) from the TS's time
   and state: substeps of the rest of the span, each halved by rodmid on Newton failure. */
static PetscErrorCode advance_span(RsStepper *s, PetscReal span, RsAdvanceResult *r)
{
    PetscReal           elapsed = 0.0, h_wanted, h_taken, t0, fnorm;
    PetscInt            its, cut, max_cutbacks;
    TSConvergedReason   reason;
    SNESConvergedReason snes_reason;
    SNES                snes;

    PetscFunctionBegin;
    for (;;) {
        /* Always try the whole rest: after a cut-back the step grows back at once. */
        h_wanted = span - elapsed;
        PetscCall(TSSetTimeStep(s->ts, h_wanted));
        PetscCall(TSGetTime(s->ts, &t0));
        PetscCall(VecCopy(s->X, s->X_prev));
        PetscCall(TSStep(s->ts));
        PetscCall(TSGetConvergedReason(s->ts, &reason));
        if (reason < 0) {
            /* rodmid left X at the start of the failing substep. */
            PetscCall(TSGetTimeStep(s->ts, &h_taken));
            PetscCall(TSGetSNES(s->ts, &snes));
            PetscCall(SNESGetConvergedReason(snes, &snes_reason));
            PetscCall(TSRodmidGetMaxCutbacks(s->ts, &max_cutbacks));
            r->diverged    = 1;
            r->t_failed    = t0;
            r->h_smallest  = h_taken;
            r->halvings    = (int)max_cutbacks;
            r->cut_factor  = 0.5;
            r->cutbacks += (int)max_cutbacks;
            r->snes_reason = SNESConvergedReasons[snes_reason];
            break;
        }
        PetscCall(TSGetTimeStep(s->ts, &h_taken));
        PetscCall(TSRodmidGetStepStats(s->ts, &its, &cut, &fnorm));
        r->cutbacks += (int)cut;
        r->newton_its += (int)its;
        r->fnorm = fnorm;
        PetscCall(book_step(s, t0, h_taken, s->X_prev, s->X, its, fnorm));
        /* Taken without a cut: that was the rest of dt (an exact test, so no drift in time). */
        if (h_taken == h_wanted) break;
        elapsed += h_taken;
    }
    PetscFunctionReturn(0);
}

/* Suzuki's five-stage composition (1990): sub-steps p, p, 1 - 4p, p, p times dt with
   p = 1/(4 - 4^(1/3)); symmetric, so order 4 from the symmetric midpoint step. Its sub-steps'
   ends, t_n + (0, 0.41, 0.83, 0.17, 0.59, 1) dt, stay inside the step, so a time function's
   kink at a step boundary (a hat's, a pulse's end) is never crossed; the triple jump's
   (1.35, -0.35, 1) dt crossed the flying spaghetti's hat kink and fell to order 1.7. */
#define SUZUKI_P 0.41449077179437571
#define SUZUKI_MIDDLE (-0.65796308717750284)

static const PetscReal SUZUKI_FRACTIONS[5] = {SUZUKI_P, SUZUKI_P, SUZUKI_MIDDLE, SUZUKI_P,
                                              SUZUKI_P};

/* ---- Error-controlled steps (traits->adaptive; docs/theory/time_integration.md) ---------- */

/* Within this of a breakpoint, a time is on it. */
static PetscReal time_tolerance(PetscReal t)
{
    return 1e-12 * PetscMax(PetscAbsReal(t), 1.0);
}

/* The end of the next step from t: the controller's step, cut at the next breakpoint and at
   `end` (the record time); a rest shorter than two steps is split evenly, so no sliver step
   follows. A breakpoint within round-off of `end` is `end` (t_n + dt need not be the
   breakpoint's own double), and one closer to t than a thousandth of the step is stepped over:
   a table's jump written as two knots 1e-7 apart (input/planar_flying_spaghetti.nml) would
   otherwise ask for a step of 1e-7, below what Newton resolves on the planar rods (their raw
   residual's floor grows as 1/h), and fixed steps step over it too. */
static PetscReal step_end(const RsStepper *s, PetscReal t, PetscReal end)
{
    const PetscReal shortest = PetscMax(time_tolerance(t), 1e-3 * s->h_next);
    PetscReal       target   = end, rest;

    for (int i = 0; i < s->n_breaks; ++i)
        if (s->breaks[i] > t + shortest) {
            if (s->breaks[i] < end - time_tolerance(end)) target = s->breaks[i];
            break;
        }
    rest = target - t;
    if (rest <= s->h_next) return target;
    if (rest < 2.0 * s->h_next) return t + 0.5 * rest;
    return t + s->h_next;
}

static PetscBool at_breakpoint(const RsStepper *s, PetscReal t)
{
    for (int i = 0; i < s->n_breaks; ++i)
        if (PetscAbsReal(s->breaks[i] - t) <= time_tolerance(t)) return PETSC_TRUE;
    return PETSC_FALSE;
}

/* One trial step from the TS's state at t to `to`: a midpoint step, or Suzuki's five; each
   sub-step's end is kept in sub_end for booking once the step is accepted. *failed: Newton
   failed in one of them (the TS's state is then not to be used). */
static PetscErrorCode trial_step(RsStepper *s, PetscReal t, PetscReal to, PetscBool *failed,
                                 RsAdvanceResult *r)
{
    const int         n = s->order == 4 ? 5 : 1;
    TSConvergedReason reason;
    PetscInt          its;
    PetscReal         fnorm;

    PetscFunctionBegin;
    *failed  = PETSC_FALSE;
    s->n_sub = 0;
    for (int k = 0; k < n; ++k) {
        s->sub_h[k] = n == 1 ? to - t : SUZUKI_FRACTIONS[k] * (to - t);
        PetscCall(TSSetTimeStep(s->ts, s->sub_h[k]));
        PetscCall(TSStep(s->ts));
        PetscCall(TSGetConvergedReason(s->ts, &reason));
        if (reason < 0) {
            SNES                snes;
            SNESConvergedReason snes_reason;
            PetscCall(TSGetSNES(s->ts, &snes));
            PetscCall(SNESGetConvergedReason(snes, &snes_reason));
            r->snes_reason = SNESConvergedReasons[snes_reason];
            *failed        = PETSC_TRUE;
            PetscFunctionReturn(0);
        }
        PetscCall(TSRodmidGetStepStats(s->ts, &its, NULL, &fnorm));
        s->sub_its[k]   = (int)its;
        s->sub_fnorm[k] = fnorm;
        r->newton_its += (int)its;
        r->fnorm = fnorm;
        PetscCall(VecCopy(s->X, s->sub_end[k]));
        s->n_sub = k + 1;
    }
    PetscCall(TSSetTime(s->ts, to)); /* exactly: a breakpoint or the record time */
    PetscFunctionReturn(0);
}

/* An accepted step from t_start: its sub-steps are booked, its start joins the past states of
   the error estimate (restarted at a breakpoint: the divided differences must not straddle a
   load's kink). */
static PetscErrorCode accept_step(RsStepper *s, PetscReal to)
{
    Vec       before = s->X_start, oldest = s->past[s->order - 1];
    PetscReal t0 = s->t_start;

    PetscFunctionBegin;
    for (int k = 0; k < s->n_sub; ++k) {
        PetscCall(book_step(s, t0, s->sub_h[k], before, s->sub_end[k], s->sub_its[k],
                            s->sub_fnorm[k]));
        t0 += s->sub_h[k];
        before = s->sub_end[k];
    }
    for (int k = s->order - 1; k > 0; --k) {
        s->past[k]   = s->past[k - 1];
        s->past_t[k] = s->past_t[k - 1];
    }
    s->past[0]   = s->X_start; /* handles swap places: no copy */
    s->past_t[0] = s->t_start;
    s->X_start   = oldest;
    s->n_past    = at_breakpoint(s, to) ? 0 : PetscMin(s->n_past + 1, s->order);
    /* With -info: every accepted step, exactly (tests/regression/solver/adaptive.py checks
       that the load kinks are step ends). */
    PetscCall(PetscInfo(s->ts, "adaptive step accepted [%.17g, %.17g]%s\n", (double)s->t_start,
                        (double)to, s->n_past == 0 ? " ending on a load kink" : ""));
    s->h_smallest = s->h_smallest > 0.0 ? PetscMin(s->h_smallest, to - s->t_start) : to - s->t_start;
    s->h_largest  = PetscMax(s->h_largest, to - s->t_start);
    PetscFunctionReturn(0);
}

/* From the TS's state at t_n to t_n + dt in steps that PETSc's TSAdapt chooses from the local
   error estimate (estimate_local_error); a Newton failure rejects the step and cuts it by
   TSAdapt's scale_solve_failed (0.25 by default), at most max_failures times in a row and not
   below dt_min. Every accepted step is a midpoint (or composed) step: its balances hold. */
static PetscErrorCode adaptive_advance(RsStepper *s, double t_n, double dt, RsAdvanceResult *r)
{
    const PetscReal end = t_n + dt;
    PetscReal       t = t_n, to, h, h_new, dt_min, dt_max, cut;
    PetscBool       failed, accept = PETSC_TRUE, retry = PETSC_FALSE;
    int             failures = 0;
    TSAdapt         adapt;

    PetscFunctionBegin;
    PetscCall(TSGetAdapt(s->ts, &adapt));
    PetscCall(TSAdaptGetStepLimits(adapt, &dt_min, &dt_max));
    PetscCall(TSAdaptGetScaleSolveFailed(adapt, &cut));
    while (end - t > time_tolerance(end)) {
        to = step_end(s, t, end);
        h  = to - t;
        /* A retry starts from X_start, restored into X: nothing to save again. */
        if (!retry) PetscCall(VecCopy(s->X, s->X_start));
        retry      = PETSC_TRUE;
        s->t_start = t;
        PetscCall(trial_step(s, t, to, &failed, r));
        if (failed) {
            PetscCall(VecCopy(s->X_start, s->X));
            PetscCall(TSSetTime(s->ts, t));
            ++r->cutbacks;
            if (++failures > s->max_failures || h <= dt_min * (1.0 + 1e-10)) {
                r->diverged   = 1;
                r->t_failed   = t;
                r->h_smallest = h;
                r->halvings   = failures - 1;
                r->cut_factor = cut;
                PetscFunctionReturn(0);
            }
            s->h_next = PetscMax(cut * h, dt_min);
            accept    = PETSC_FALSE;
            continue;
        }
        failures = 0;
        /* accept goes in as "the last attempt was accepted" (a rejection shortens more). */
        PetscCall(TSAdaptChoose(adapt, s->ts, h, NULL, &h_new, &accept));
        s->h_next = h_new;
        if (!accept) {
            PetscCall(VecCopy(s->X_start, s->X));
            PetscCall(TSSetTime(s->ts, t));
            ++s->rejected;
            continue;
        }
        PetscCall(accept_step(s, to));
        ++r->substeps;
        t     = to;
        retry = PETSC_FALSE;
    }
    PetscCall(TSSetTime(s->ts, end));
    PetscFunctionReturn(0);
}

static PetscErrorCode stepper_advance(RsStepper *s, double t_n, double dt, double *x,
                                      RsAdvanceResult *r)
{
    PetscScalar       *a;
    const PetscScalar *x0;
    PetscInt           steps_before, steps_after;

    PetscFunctionBegin;
    if (s->distributed) {
        PetscCall(scatter_owned(x, s->state_lo, s->state_hi, s->X));
    } else {
        PetscCall(VecGetArray(s->X, &a));
        PetscCall(PetscArraycpy(a, x, s->n_state));
        PetscCall(VecRestoreArray(s->X, &a));
    }
    PetscCall(TSSetTime(s->ts, t_n));
    PetscCall(TSSetMaxTime(s->ts, t_n + dt));
    PetscCall(TSGetStepNumber(s->ts, &steps_before));
    if (s->adaptive) {
        PetscCall(adaptive_advance(s, t_n, dt, r));
    } else if (s->order == 4) {
        for (int k = 0; k < 5 && !r->diverged; ++k)
            PetscCall(advance_span(s, SUZUKI_FRACTIONS[k] * dt, r));
        if (r->diverged) {
            /* A composed step is whole or not at all: x keeps the state at t_n. */
            r->t_failed = t_n;
            PetscFunctionReturn(0);
        }
        /* The spans add up to dt up to round-off; the step ends at t_n + dt exactly. */
        PetscCall(TSSetTime(s->ts, t_n + dt));
    } else {
        PetscCall(advance_span(s, dt, r));
    }
    PetscCall(TSGetStepNumber(s->ts, &steps_after));
    if (!s->adaptive) r->substeps = (int)(steps_after - steps_before);
    if (s->distributed) {
        PetscCall(gather(s->gather_state, s->X, s->x_all));
        PetscCall(VecGetArrayRead(s->x_all, &x0));
    } else {
        PetscCall(VecGetArrayRead(s->X, &x0));
    }
    PetscCall(PetscArraycpy(x, x0, s->n_state));
    PetscCall(VecRestoreArrayRead(s->distributed ? s->x_all : s->X, &x0));
    PetscFunctionReturn(0);
}

int rs_stepper_advance(void *handle, double t_n, double dt, double *x, int *substeps, int *cutbacks,
                       int *newton_its, double *fnorm, char *errmsg, int errlen)
{
    RsStepper      *s       = (RsStepper *)handle;
    RsErrorCapture  capture = {"", 0};
    RsAdvanceResult r;
    PetscErrorCode  ierr;

    memset(&r, 0, sizeof(r));
    if (errmsg && errlen > 0) errmsg[0] = '\0';
    if (!s) {
        set_message(errmsg, errlen, "rod stepper: advance on a stepper that was not created");
        return RS_STEPPER_BAD_ARGUMENT;
    }
    if (!(dt > 0.0)) {
        set_message(errmsg, errlen, "rod stepper: the step dt = %g at t = %g must be positive", dt,
                    t_n);
        return RS_STEPPER_BAD_ARGUMENT;
    }
    enter_petsc(s);
    PetscPushErrorHandler(rs_capture_petsc_error, &capture);
    ierr = stepper_advance(s, t_n, dt, x, &r);
    PetscPopErrorHandler();
    leave_petsc(s);
    if (substeps) *substeps = r.substeps;
    if (cutbacks) *cutbacks = r.cutbacks;
    if (newton_its) *newton_its = r.newton_its;
    if (fnorm) *fnorm = r.fnorm;
    if (ierr) {
        set_petsc_message(errmsg, errlen, "rod stepper: advance failed", ierr, &capture);
        return (int)ierr;
    }
    if (r.diverged && r.cut_factor == 0.5) {
        set_message(errmsg, errlen,
                    "Newton did not converge at t = %.10g after %d halvings of the step (smallest "
                    "step %.6g); "
                    "last SNES reason %s. The state returned is the last good one, at t = %.10g.",
                    r.t_failed, r.halvings, r.h_smallest, r.snes_reason, r.t_failed);
        return RS_STEPPER_DIVERGED;
    }
    if (r.diverged) {
        set_message(errmsg, errlen,
                    "Newton did not converge at t = %.10g after %d cut-backs of the step by %g "
                    "each (smallest step %.6g); last SNES reason %s. The state returned is the "
                    "last good one, at t = %.10g.",
                    r.t_failed, r.halvings, r.cut_factor, r.h_smallest, r.snes_reason, r.t_failed);
        return RS_STEPPER_DIVERGED;
    }
    return 0;
}

/* ---- Queries and destroy -------------------------------------------------------------------- */

static PetscErrorCode stepper_settings(RsStepper *s, double *atol, double *rtol, double *stol,
                                       int *max_it, int *max_funcs, int *max_cutbacks, char *types,
                                       int length)
{
    SNES               snes;
    SNESLineSearch     linesearch;
    KSP                ksp;
    PC                 pc;
    SNESType           snes_type;
    SNESLineSearchType ls_type;
    KSPType            ksp_type;
    PCType             pc_type;
    MatSolverType      solver = NULL;
    PetscReal          a, r, st;
    PetscInt           it, nf;
    PetscBool          is_factor;
    PetscInt           cutbacks;

    PetscFunctionBegin;
    PetscCall(TSGetSNES(s->ts, &snes));
    PetscCall(SNESGetTolerances(snes, &a, &r, &st, &it, &nf));
    PetscCall(SNESGetType(snes, &snes_type));
    PetscCall(SNESGetLineSearch(snes, &linesearch));
    PetscCall(SNESLineSearchGetType(linesearch, &ls_type));
    PetscCall(SNESGetKSP(snes, &ksp));
    PetscCall(KSPGetType(ksp, &ksp_type));
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PCGetType(pc, &pc_type));
    PetscCall(
        PetscObjectTypeCompareAny((PetscObject)pc, &is_factor, PCLU, PCCHOLESKY, PCILU, PCICC, ""));
    if (is_factor) PetscCall(PCFactorGetMatSolverType(pc, &solver));
    if (atol) *atol = a;
    if (rtol) *rtol = r;
    if (stol) *stol = st;
    if (max_it) *max_it = (int)it;
    if (max_funcs) *max_funcs = (int)nf;
    PetscCall(TSRodmidGetMaxCutbacks(s->ts, &cutbacks));
    if (max_cutbacks) *max_cutbacks = (int)cutbacks;
    if (types && length > 0)
        snprintf(types, (size_t)length, "snes %s linesearch %s ksp %s pc %s solver %s",
                 snes_type ? snes_type : "?", ls_type ? ls_type : "?", ksp_type ? ksp_type : "?",
                 pc_type ? pc_type : "?", solver ? solver : "none");
    PetscFunctionReturn(0);
}

int rs_stepper_solver_settings(void *handle, double *atol, double *rtol, double *stol, int *max_it,
                               int *max_funcs, int *max_cutbacks, char *types, int length)
{
    RsErrorCapture capture = {"", 0};
    PetscErrorCode ierr;

    if (!handle) return RS_STEPPER_BAD_ARGUMENT;
    enter_petsc((RsStepper *)handle);
    PetscPushErrorHandler(rs_capture_petsc_error, &capture);
    ierr = stepper_settings((RsStepper *)handle, atol, rtol, stol, max_it, max_funcs, max_cutbacks,
                            types, length);
    PetscPopErrorHandler();
    leave_petsc((RsStepper *)handle);
    return (int)ierr;
}

int rs_stepper_run_stats(void *handle, int *jacobians, int *floor_steps)
{
    RsStepper     *s       = (RsStepper *)handle;
    RsErrorCapture capture = {"", 0};
    PetscInt       count[2] = {0, 0};
    PetscErrorCode ierr;

    if (!s || !jacobians || !floor_steps) return RS_STEPPER_BAD_ARGUMENT;
    enter_petsc(s);
    PetscPushErrorHandler(rs_capture_petsc_error, &capture);
    ierr = TSRodmidGetRunStats(s->ts, &count[0], &count[1]);
    PetscPopErrorHandler();
    leave_petsc(s);
    *jacobians   = (int)count[0];
    *floor_steps = (int)count[1];
    return (int)ierr;
}

static PetscErrorCode stepper_view(RsStepper *s, const char *path)
{
    PetscViewer viewer;

    PetscFunctionBegin;
    if (!path || !path[0]) {
        PetscCall(TSView(s->ts, PETSC_VIEWER_STDOUT_(s->comm)));
    } else {
        PetscCall(PetscViewerASCIIOpen(s->comm, path, &viewer));
        PetscCall(TSView(s->ts, viewer));
        PetscCall(PetscViewerDestroy(&viewer));
    }
    PetscFunctionReturn(0);
}

int rs_stepper_view(void *handle, const char *path)
{
    RsErrorCapture capture = {"", 0};
    PetscErrorCode ierr;

    if (!handle) return RS_STEPPER_BAD_ARGUMENT;
    enter_petsc((RsStepper *)handle);
    PetscPushErrorHandler(rs_capture_petsc_error, &capture);
    ierr = stepper_view((RsStepper *)handle, path);
    PetscPopErrorHandler();
    leave_petsc((RsStepper *)handle);
    return (int)ierr;
}

/* ---- Bordered solves ----------------------------------------------------------------------- */

/* The Jacobian values into J (the CSR order of the pattern, as step_jacobian writes them) and
   its factorization by the stepper's own KSP and PC: the chain LU for one rod, PETSc's LU or
   MUMPS as the stepper chose them, and the same options. The symbolic phase is the stepper's,
   done once per pattern; each call redoes the numeric one. */
static PetscErrorCode stepper_factor(RsStepper *s, const double *values, int *failed)
{
    SNES               snes;
    KSP                ksp;
    PC                 pc;
    PetscScalar       *a;
    PCFailedReason     reason;

    PetscFunctionBegin;
    PetscCall(MatSeqAIJGetArray(s->J, &a));
    PetscCall(PetscArraycpy(a, values, s->nnz));
    PetscCall(MatSeqAIJRestoreArray(s->J, &a));
    PetscCall(MatAssemblyBegin(s->J, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(s->J, MAT_FINAL_ASSEMBLY));
    PetscCall(TSGetSNES(s->ts, &snes));
    PetscCall(SNESGetKSP(snes, &ksp));
    PetscCall(KSPSetOperators(ksp, s->J, s->J));
    PetscCall(KSPSetUp(ksp));
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PCGetFailedReason(pc, &reason));
    *failed = reason != PC_NOERROR;
    if (!s->rhs) {
        PetscCall(VecCreateSeq(PETSC_COMM_SELF, s->n_unknown, &s->rhs));
        PetscCall(VecDuplicate(s->rhs, &s->sol));
    }
    PetscFunctionReturn(0);
}

int rs_stepper_factor(void *handle, const double *values, int *singular, char *errmsg,
                      int errlen)
{
    RsStepper     *s       = (RsStepper *)handle;
    RsErrorCapture capture = {"", 0};
    PetscErrorCode ierr;

    if (errmsg && errlen > 0) errmsg[0] = '\0';
    if (!s || !singular) {
        set_message(errmsg, errlen, "rod stepper: factor without a stepper");
        return RS_STEPPER_BAD_ARGUMENT;
    }
    if (s->distributed) {
        set_message(errmsg, errlen, "rod stepper: bordered solves (arc-length continuation) "
                                    "on a system shared by the ranks are not implemented; "
                                    "run the scene on one rank");
        return RS_STEPPER_BAD_ARGUMENT;
    }
    enter_petsc(s);
    PetscPushErrorHandler(rs_capture_petsc_error, &capture);
    ierr = stepper_factor(s, values, singular);
    PetscPopErrorHandler();
    leave_petsc(s);
    if (ierr) {
        set_petsc_message(errmsg, errlen, "rod stepper: factorization failed", ierr, &capture);
        return (int)ierr;
    }
    return 0;
}

static PetscErrorCode stepper_solve(RsStepper *s, const double *rhs, double *sol, int *failed)
{
    SNES               snes;
    KSP                ksp;
    KSPConvergedReason reason;
    PetscScalar       *a;
    const PetscScalar *b;

    PetscFunctionBegin;
    PetscCall(TSGetSNES(s->ts, &snes));
    PetscCall(SNESGetKSP(snes, &ksp));
    PetscCall(VecGetArray(s->rhs, &a));
    PetscCall(PetscArraycpy(a, rhs, s->n_unknown));
    PetscCall(VecRestoreArray(s->rhs, &a));
    PetscCall(KSPSolve(ksp, s->rhs, s->sol));
    PetscCall(KSPGetConvergedReason(ksp, &reason));
    *failed = reason < 0;
    PetscCall(VecGetArrayRead(s->sol, &b));
    PetscCall(PetscArraycpy(sol, b, s->n_unknown));
    PetscCall(VecRestoreArrayRead(s->sol, &b));
    PetscFunctionReturn(0);
}

int rs_stepper_solve(void *handle, const double *rhs, double *sol, int *failed, char *errmsg,
                     int errlen)
{
    RsStepper     *s       = (RsStepper *)handle;
    RsErrorCapture capture = {"", 0};
    PetscErrorCode ierr;

    if (errmsg && errlen > 0) errmsg[0] = '\0';
    if (!s || !s->rhs || !failed) {
        set_message(errmsg, errlen, "rod stepper: solve before a factorization");
        return RS_STEPPER_BAD_ARGUMENT;
    }
    enter_petsc(s);
    PetscPushErrorHandler(rs_capture_petsc_error, &capture);
    ierr = stepper_solve(s, rhs, sol, failed);
    PetscPopErrorHandler();
    leave_petsc(s);
    if (ierr) {
        set_petsc_message(errmsg, errlen, "rod stepper: linear solve failed", ierr, &capture);
        return (int)ierr;
    }
    return 0;
}

int rs_stepper_destroy(void **handle)
{
    if (!handle || !*handle) return 0;
    stepper_free((RsStepper *)*handle);
    *handle = NULL;
    return 0;
}

int rs_stepper_set_admissible(void *handle, rs_cb_admissible admissible)
{
    RsStepper     *s = (RsStepper *)handle;
    PetscErrorCode ierr;

    if (!s) return RS_STEPPER_BAD_ARGUMENT;
    s->admissible = admissible;
    enter_petsc(s);
    ierr = TSRodmidSetAdmissible(s->ts, admissible ? step_admissible : NULL);
    leave_petsc(s);
    return (int)ierr;
}

int rs_stepper_shortened_steps(void *handle, int *shortened)
{
    RsStepper     *s = (RsStepper *)handle;
    PetscInt       n = 0;
    PetscErrorCode ierr;

    if (!s || !shortened) return RS_STEPPER_BAD_ARGUMENT;
    enter_petsc(s);
    ierr = TSRodmidGetShortenedSteps(s->ts, &n);
    leave_petsc(s);
    *shortened = (int)n;
    return (int)ierr;
}

static int compare_times(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int rs_stepper_set_breakpoints(void *handle, int n, const double *times)
{
    RsStepper *s = (RsStepper *)handle;
    double    *copy;

    if (!s || n < 0 || (n > 0 && !times)) return RS_STEPPER_BAD_ARGUMENT;
    copy = n > 0 ? malloc((size_t)n * sizeof(*copy)) : NULL;
    if (n > 0 && !copy) return RS_STEPPER_BAD_ARGUMENT;
    if (n > 0) {
        memcpy(copy, times, (size_t)n * sizeof(*copy));
        qsort(copy, (size_t)n, sizeof(*copy), compare_times);
    }
    free(s->breaks);
    s->breaks   = copy;
    s->n_breaks = n;
    return 0;
}

int rs_stepper_adaptive_stats(void *handle, int *rejected, double *h_smallest, double *h_largest)
{
    const RsStepper *s = (const RsStepper *)handle;

    if (!s) return RS_STEPPER_BAD_ARGUMENT;
    if (rejected) *rejected = s->rejected;
    if (h_smallest) *h_smallest = s->h_smallest;
    if (h_largest) *h_largest = s->h_largest;
    return 0;
}

static PetscErrorCode stepper_set_error_entries(RsStepper *s, const int *weigh)
{
    Vec          atol, rtol;
    PetscScalar *a, *r;
    PetscReal    atol_value, rtol_value;
    PetscInt     lo, hi;

    PetscFunctionBegin;
    PetscCall(TSGetTolerances(s->ts, &atol_value, NULL, &rtol_value, NULL));
    PetscCall(VecDuplicate(s->X, &atol));
    PetscCall(VecDuplicate(s->X, &rtol));
    PetscCall(VecGetOwnershipRange(s->X, &lo, &hi));
    PetscCall(VecGetArray(atol, &a));
    PetscCall(VecGetArray(rtol, &r));
    for (PetscInt i = lo; i < hi; ++i) {
        /* A left-out entry: a tolerance no difference comes near. */
        a[i - lo] = weigh[i] ? atol_value : 1e300;
        r[i - lo] = weigh[i] ? rtol_value : 0.0;
    }
    PetscCall(VecRestoreArray(rtol, &r));
    PetscCall(VecRestoreArray(atol, &a));
    PetscCall(TSSetTolerances(s->ts, atol_value, atol, rtol_value, rtol));
    PetscCall(VecDestroy(&atol));
    PetscCall(VecDestroy(&rtol));
    PetscFunctionReturn(0);
}

int rs_stepper_set_error_entries(void *handle, int n, const int *weigh)
{
    RsStepper     *s = (RsStepper *)handle;
    PetscErrorCode ierr;

    if (!s || !s->adaptive || n != s->n_state || !weigh) return RS_STEPPER_BAD_ARGUMENT;
    enter_petsc(s);
    ierr = stepper_set_error_entries(s, weigh);
    leave_petsc(s);
    return (int)ierr;
}
