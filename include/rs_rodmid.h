/* The rodmid time stepper of rodsolve: a PETSc TS type that advances one implicit step of a
   user-defined *step problem* (DESIGN.md §3, "The midpoint stepper").

   A step from (t_n, X_n) with step h solves F(Y; X_n, t_n, h) = 0 for the step unknown Y with
   the SNES of the TS, then sets X_{n+1} = U(Y, X_n). Y is a Vec of its own and may differ in
   size from the TS state X (condensed element stresses, multiplicative rotation updates), which
   is why PETSc's TSTHETA cannot serve. Defaults: Y has X's layout, the predictor is Y0 = X_n
   and the update is X_{n+1} = Y.

   On a SNES failure (any SNESConvergedReason < 0, including a domain error raised by the
   residual with SNESSetFunctionDomainError) the step is halved and retried from X_n, at most
   max_cutbacks times; then ts->reason = TS_DIVERGED_NONLINEAR_SOLVE and the TS state stays
   X_n. After TSStep, TSGetTimeStep returns the step actually taken (or, after a failure, the
   smallest one tried): a cut-back does not set the next step, the caller does (as
   rs_stepper_advance does for every substep).

   Options: -ts_rodmid_max_cutbacks <n> (default 6, as &solver max_cutbacks). PETSc is pinned
   to 3.18.x because this type is built against PETSc's private TS header
   (cmake/RodsolveDeps.cmake). */
#ifndef RS_RODMID_H
#define RS_RODMID_H

#include <petscts.h>

/* The name under which the type is registered: TSSetType(ts, TSRODMID). */
#define TSRODMID "rodmid"

/* F = F(Y; X_n, t_n, h). Raise SNESSetFunctionDomainError on the TS's SNES for an invalid Y
   (the step is cut, not the run); return a PETSc error only for fatal problems. */
typedef PetscErrorCode (*RsStepResidual)(PetscReal t_n, PetscReal h, Vec X_n, Vec Y, Vec F,
                                         void *ctx);
/* J = dF/dY at Y; J is the matrix given to TSRodmidSetStepProblem (assemble it). */
typedef PetscErrorCode (*RsStepJacobian)(PetscReal t_n, PetscReal h, Vec X_n, Vec Y, Mat J,
                                         void *ctx);
/* Predictor: fill Y with the first Newton iterate. */
typedef PetscErrorCode (*RsStepVecFn)(PetscReal t_n, PetscReal h, Vec X_n, Vec Y, void *ctx);
/* Update: X_{n+1} from the converged Y and X_n. */
typedef PetscErrorCode (*RsStepUpdate)(PetscReal t_n, PetscReal h, Vec X_n, Vec Y, Vec X_np1,
                                       void *ctx);

/* Admissible: *ok false when Y is no admissible iterate of the step from X_n (contact: a
   pair of contact points would cross the barrier's wall on the way from X_n; the residual
   then raises a domain error). Collective: every rank gets the same answer. */
typedef PetscErrorCode (*RsStepAdmissible)(PetscReal t_n, PetscReal h, Vec X_n, Vec Y,
                                           PetscBool *ok, void *ctx);

/* The weighted norm of the local error of the step just taken (ts->vec_sol against the state
   before it; TSErrorWeightedNorm with the TS's tolerances), and its order in h (the exponent
   of h in the local error, so the controller's step factor is wlte^(-1/order)); wlte < 0: no
   estimate for this step (the step is accepted as it is). */
typedef PetscErrorCode (*RsStepErrorEstimate)(TS ts, NormType type, PetscInt *order,
                                              PetscReal *wlte, void *ctx);

/* Register TSRODMID with TSRegister; safe to call any number of times (also after a PETSc
   finalize/initialize cycle). */
PETSC_EXTERN PetscErrorCode rs_rodmid_register(void);

/* Define the step problem of a TSRODMID. Y_template: a Vec with Y's layout (duplicated; NULL:
   X's layout). J: the Jacobian matrix, referenced and reused for every step, so that its
   nonzero pattern and with it the symbolic factorization are kept (DESIGN.md §3). predictor
   and update may be NULL (defaults above; a NULL update needs Y of X's size). No-op for other
   TS types. */
PETSC_EXTERN PetscErrorCode TSRodmidSetStepProblem(TS ts, Vec Y_template, Mat J,
                                                   RsStepResidual residual,
                                                   RsStepJacobian jacobian,
                                                   RsStepVecFn predictor, RsStepUpdate update,
                                                   void *ctx);
/* A feasible-step filter (as in Incremental Potential Contact, Li et al. 2020): before each
   line search the Newton step is halved (at most 30 times) until its full step is admissible,
   so an iterate that overshoots into an invalid state shortens the Newton step instead of
   cutting the time step; at most 8 Newton steps of one solve are shortened (beyond, the time
   step is cut: the solution lies outside the admissible set). A prediction it refuses is
   pulled back towards the prediction of a zero step. NULL: none (the default). May be set
   after TSSetUp. */
PETSC_EXTERN PetscErrorCode TSRodmidSetAdmissible(TS ts, RsStepAdmissible admissible);
/* The local error estimate TSAdaptChoose uses (ts->ops->evaluatewlte, so PETSc's adaptors
   basic and dsp choose the steps): a rodmid step alone cannot estimate its error, the caller
   that composes and keeps the accepted states can. NULL: none (TSEvaluateWLTE reports no
   estimate). */
PETSC_EXTERN PetscErrorCode TSRodmidSetErrorEstimate(TS ts, RsStepErrorEstimate estimate, void *ctx);
/* Maximum number of halvings of one step before the TS reports TS_DIVERGED_NONLINEAR_SOLVE. */
PETSC_EXTERN PetscErrorCode TSRodmidSetMaxCutbacks(TS ts, PetscInt n);
/* The current limit of halvings of one step. */
PETSC_EXTERN PetscErrorCode TSRodmidGetMaxCutbacks(TS ts, PetscInt *n);
/* Statistics of the last accepted step: SNES iterations, halvings, final residual norm. Any
   pointer may be NULL. After a failed step they still describe the last accepted one. */
PETSC_EXTERN PetscErrorCode TSRodmidGetStepStats(TS ts, PetscInt *newton_its, PetscInt *cutbacks,
                                                 PetscReal *fnorm);
/* Over the run: Jacobians computed (each one a numeric factorization), and accepted steps
   whose Newton residual ended above the SNES atol but at the rounding floor ||J u||,
   u_i = +-eps |Y_i| (Newton run to stagnation; the stopping test is rodmid's).
   Option -ts_rodmid_reuse_jacobian <ratio in [0, 1)>: keep the factored Jacobian across
   iterations and steps while its full step cuts the residual norm at least by the ratio
   (0, the default: a new Jacobian at every iteration). */
PETSC_EXTERN PetscErrorCode TSRodmidGetRunStats(TS ts, PetscInt *jacobians, PetscInt *floor_steps);
/* Over the run: Newton steps and predictions the feasible-step filter shortened
   (TSRodmidSetAdmissible). */
PETSC_EXTERN PetscErrorCode TSRodmidGetShortenedSteps(TS ts, PetscInt *shortened);

#endif
