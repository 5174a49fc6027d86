/* The rod stepper: what Fortran calls (through bind(C), src/solver/rod_stepper.f90) to advance
   one rod with a rodmid TS on PETSC_COMM_SELF (DESIGN.md §3 and §5), and the run's PETSc
   options (src/solver/petsc_init.c).

   Callbacks get raw arrays (kernels never see a PETSc handle, DESIGN.md §2) and return
       0  ok,
       1  invalid state (NaN, inverted element): only the residual and the Jacobian may say
          so; the SNES diverges with a domain error and the step is halved, the run goes on,
       other values: fatal, the advance stops with an error naming the callback.
   x_n is the state at the start of the (sub)step and has n_state entries; y and f have
   n_unknown entries; the Jacobian values come in the order of the CSR pattern given at
   create (nnz = row_ptr[n_unknown] entries). */
#ifndef RS_ROD_STEPPER_H
#define RS_ROD_STEPPER_H

#include <stdbool.h>

/* Return value of rs_stepper_advance when Newton failed after all cut-backs: x holds the last
   good state. Every other non-zero value is an error (PETSc or a fatal callback). */
#define RS_STEPPER_DIVERGED 1
/* Return value for invalid arguments (sizes, pattern, callbacks); PETSc's codes are >= 55. */
#define RS_STEPPER_BAD_ARGUMENT 2

typedef int (*rs_cb_residual)(void *ctx, double t_n, double h, const double *x_n, const double *y,
                              double *f);
typedef int (*rs_cb_jacobian)(void *ctx, double t_n, double h, const double *x_n, const double *y,
                              double *values);
/* Predictor: the first Newton iterate y (default y = x_n, needs n_unknown = n_state). */
typedef int (*rs_cb_vec)(void *ctx, double t_n, double h, const double *x_n, double *y);
/* Update: x_{n+1} from the converged y (default x_{n+1} = y). */
typedef int (*rs_cb_update)(void *ctx, double t_n, double h, const double *x_n, const double *y,
                            double *x_np1);
/* After each accepted (sub)step [t_n, t_n + h]: energy work, history, Newton statistics. */
typedef int (*rs_cb_poststep)(void *ctx, double t_n, double h, const double *x_n,
                              const double *x_np1, int newton_its, double fnorm);

/* Admissible: 0 when y is an admissible iterate of the step from x_n, 1 when it is not (a
   residual at y would report an invalid state). */
typedef int (*rs_cb_admissible)(void *ctx, double t_n, double h, const double *x_n,
                                const double *y);

/* What a stepper is built with besides its pattern and callbacks (one struct, filled in
   Fortran as the bind(C) type stepper_traits_t of src/solver/rod_stepper.f90, from the scene's
   &solver values and the formulation's traits, rs_formulations_formulation):
   newton_atol, newton_rtol, max_newton and max_cutbacks are scene values: they enter the
   option database as defaults below the input's petsc_options and the command line (see
   rs_petsc_apply_options), then TSSetFromOptions reads everything.
   jacobian_reuse: 0 for Newton's method; a ratio in (0, 1) keeps the factored Jacobian while
   each Newton iteration cuts the residual norm at least by it (-ts_rodmid_reuse_jacobian,
   include/rs_rodmid.h; ignored for a linear step).
   The flags are the formulation's solver traits:
   native_lu: the Jacobian needs no pivoting, so PETSc's own LU replaces the chain LU
     (rodchain), with a nested-dissection ordering, or the natural one when banded_unknowns
     says the unknowns are numbered for a narrow band; -pc_factor_mat_solver_type overrides;
   full_newton: Newton takes full steps (line search basic) instead of backtracking (bt);
     -snes_linesearch_type overrides;
   linear_step: the step problem is affine in Y (seed 004's semi-implicit scheme): the SNES is
     KSPONLY, i.e. one residual, one Jacobian and one linear solve per step, no Newton loop and
     no norms (-snes_type overrides).
   order: 2, a step of the advance is one midpoint step (with its cut-backs); 4, it is the
     symmetric composition of five, of p dt, p dt, (1 - 4p) dt, p dt, p dt with
     p = 1/(4 - 4^(1/3)) (Suzuki 1990: order 4 from any symmetric step of order 2; every
     sub-step keeps its own balance laws; docs/theory/time_integration.md).
   adaptive: the steps inside each advance are chosen by PETSc's TSAdapt (basic; -ts_adapt_*
     options override) from a local error estimate (rs_stepper_set_breakpoints,
     docs/theory/time_integration.md): atol and rtol weigh the state's entries
     (TSErrorWeightedNorm), dt_min and dt_max bound the step, dt_initial is the first one.
     A Newton failure rejects the step like an error that is too large (rodmid then does not
     halve on its own); max_cutbacks bounds the failures in a row.
   The field order is the Fortran type's: change both together. */
struct rs_stepper_traits {
    double newton_atol;
    double newton_rtol;
    double jacobian_reuse;
    int    max_newton;
    int    max_cutbacks;
    bool   native_lu;
    bool   banded_unknowns;
    bool   full_newton;
    bool   linear_step;
    int    order;
    bool   adaptive;
    double atol;
    double rtol;
    double dt_min;
    double dt_max;
    double dt_initial;
};

/* Create a stepper. row_ptr (n_unknown + 1 entries) and cols give the CSR pattern of dF/dY,
   0-based with strictly increasing columns in each row; the matrix is preallocated exactly
   from it and kept, so MUMPS analyses it once per stepper (DESIGN.md §3). traits (required):
   the Newton settings and the solver flags above; the stepper keeps no pointer to it.
   owned (NULL for a system of one rank on PETSC_COMM_SELF): a system shared by all ranks on
   PETSC_COMM_WORLD (DESIGN.md §5), this rank owning the state entries [owned[0], owned[1])
   and the unknowns [owned[2], owned[3]) (0-based); the LU package is then MUMPS. row_ptr and
   cols are then the whole pattern on every rank; the callbacks get the whole x_n, y
   (gathered) and fill the owned rows of f and of the values (other entries are ignored); x of
   advance is whole on every rank. A callback status is agreed by all ranks (the largest).
   block_lengths (NULL, or n_blocks <= 1: one LU of the whole Jacobian): the unknowns in
   n_blocks consecutive blocks (a coupled system: one per rod with the coupling unknowns it
   owns; on several ranks each rank's range is whole blocks); the linear solver is then GMRES
   with block Jacobi, every block factored exactly (docs/performance.md, "Bundles: block
   Jacobi"); -ksp_type preonly -pc_type lu -pc_factor_mat_solver_type mumps restores the
   direct solve.
   Returns 0, or non-zero with a message in errmsg (errlen bytes, NUL-terminated). */
int rs_stepper_create(void **handle, int n_state, int n_unknown, const int *row_ptr,
                      const int *cols, rs_cb_residual residual, rs_cb_jacobian jacobian,
                      rs_cb_vec predictor, rs_cb_update update, rs_cb_poststep poststep,
                      void *ctx, const struct rs_stepper_traits *traits, const int *owned,
                      int n_blocks, const int *block_lengths, char *errmsg, int errlen);

/* A system shared by the ranks (owned given to rs_stepper_create): the 0-based entries of the
   state and of the unknowns this rank's callbacks read (its rows' rods and their neighbours);
   before each evaluation only these are gathered into the whole-length arrays the callbacks
   see (the others keep older values), instead of the whole system. Without this call, or on
   one rank, everything is gathered. Returns 0, or non-zero with the message in errmsg. */
int rs_stepper_set_needed(void *handle, int n_state, const int *state_entries, int n_unknown,
                          const int *unknown_entries, char *errmsg, int errlen);

/* Advance x from t_n to exactly t_n + dt: substeps of dt - (time done), each halved by the
   TS on Newton failure, so the step grows back after a cut. Outputs: accepted substeps,
   total halvings and Newton iterations over them, final residual norm of the last one.
   Returns 0; RS_STEPPER_DIVERGED with x = the state at the start of the failing substep and a
   message naming that time; or another non-zero code on an error (PETSc, a fatal callback
   status, bad arguments), with x unchanged and the message in errmsg. */
int rs_stepper_advance(void *handle, double t_n, double dt, double *x, int *substeps,
                       int *cutbacks, int *newton_its, double *fnorm, char *errmsg, int errlen);

/* The solver actually configured (after all options): SNES tolerances, maximum iterations and
   function evaluations, maximum cut-backs, and "snes <type> linesearch <type> ksp <type> pc
   <type> solver <package>" in `types` (NUL-terminated, at most `length` bytes). */
int rs_stepper_solver_settings(void *handle, double *atol, double *rtol, double *stol,
                               int *max_it, int *max_funcs, int *max_cutbacks, char *types,
                               int length);

/* Since the stepper was created: Jacobians computed (and factored), and accepted steps whose
   Newton residual ended above newton_atol at the rounding floor (include/rs_rodmid.h). */
int rs_stepper_run_stats(void *handle, int *jacobians, int *floor_steps);

/* The feasible-step filter of the Newton solves (TSRodmidSetAdmissible, include/rs_rodmid.h):
   each Newton step is shortened until its full step is admissible by `admissible` (on a
   shared system every rank asks its own rows' part, and the ranks agree). NULL removes it.
   Newton steps it shortened since the stepper was created: rs_stepper_shortened_steps.
   Returns 0, or RS_STEPPER_BAD_ARGUMENT without a handle. */
int rs_stepper_set_admissible(void *handle, rs_cb_admissible admissible);
int rs_stepper_shortened_steps(void *handle, int *shortened);

/* Adaptive steppers (traits.adaptive): the times where a load's time function has a kink or a
   jump (pulse and ramp ends, a hat's peak, table knots), which the steps hit exactly and across
   which the error estimate starts afresh; n of them, any order, copied. */
int rs_stepper_set_breakpoints(void *handle, int n, const double *times);
/* Adaptive steppers: the state entries whose local error is controlled (weigh[i] != 0, n =
   n_state entries of the whole state, 0-based as X); the others (midpoint multipliers and
   stresses, jumping rotation vectors) are left out of the error norm. Default: all. */
int rs_stepper_set_error_entries(void *handle, int n, const int *weigh);
/* Adaptive steppers: steps the error control rejected over the run (Newton failures count as
   cut-backs), and the smallest and largest accepted steps (0 before any). */
int rs_stepper_adaptive_stats(void *handle, int *rejected, double *h_smallest, double *h_largest);

/* TSView of the stepper's TS (with its SNES, KSP and PC) into the file `path` (NULL or "":
   standard output). */
int rs_stepper_view(void *handle, const char *path);

/* Bordered solves of a Newton method the caller runs itself (arc-length continuation,
   src/solver/arc_length.f90): the Jacobian `values` (in the order of the pattern) factored by
   the stepper's own linear solver (the chain LU for one rod, or what the options chose; the
   symbolic phase is shared with the steps), then solved for any number of right-hand sides of
   n_unknown values each. *singular: the factorization met a zero pivot; *failed: the linear
   solve did not converge. Not for a system shared by the ranks (RS_STEPPER_BAD_ARGUMENT).
   Return 0, or non-zero with the message in errmsg. */
int rs_stepper_factor(void *handle, const double *values, int *singular, char *errmsg,
                      int errlen);
int rs_stepper_solve(void *handle, const double *rhs, double *sol, int *failed, char *errmsg,
                     int errlen);

/* Free the stepper and set *handle to NULL; a NULL handle is fine. */
int rs_stepper_destroy(void **handle);

/* ---- The run's PETSc options (src/solver/petsc_init.c; DESIGN.md §3 "Options") ----------

   Precedence: scene values < the input's petsc_options < the command line. The command line
   layer (with PETSC_OPTIONS and .petscrc files, read as PetscInitialize read them) is captured
   by rs_petsc_initialize and never overwritten; a layer only sets the options that no higher
   layer names, so the order of the calls does not matter.

   rs_petsc_apply_options(scene_options, user_options):
     user_options != NULL: replace the petsc_options layer (names only the old one set are
       cleared); the driver calls this once at start-up with the input's petsc_options.
     scene_options != NULL: insert scene values under the two other layers. Each stepper does
       this with the defaults built from its scene values (so sweeps of newton_atol work:
       every member's stepper reads its own values), and the driver may do it at start-up.
   Non-collective (PETSC_COMM_SELF parsing), so ranks may create steppers independently.
   Returns 0, or non-zero with a message (e.g. PETSc could not parse the string). */
int rs_petsc_apply_options(const char *scene_options, const char *user_options, char *errmsg,
                           int errlen);

/* All options in the database ("-name value ..."), for the output file. Copies at most
   length - 1 characters and a NUL; returns the full length (>= length: truncated), or -1. */
int rs_petsc_options_text(char *buffer, int length);
/* The user's options (command line, petsc_options) nothing has read: "-name (where); ..."
   into buffer, their count returned (-1 on a PETSc error). */
int rs_petsc_unused_options(char *buffer, int length);

/* Start PETSc's default event logging (what -log_view does), for rs_petsc_event_count. */
int rs_petsc_log_begin(void);

/* How often the event `name` (e.g. "MatLUFactorSym") ran in the current logging stage since
   logging began; 0 for an event not registered yet. Returns 0, 1 if logging is off. */
int rs_petsc_event_count(const char *name, int *count);

#endif
