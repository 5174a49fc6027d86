/* The rodmid TS type (DESIGN.md §3, "The midpoint stepper"; interface in include/rs_rodmid.h).

   One TSStep solves the user's step problem F(Y; X_n, t_n, h) = 0 with the SNES of the TS and
   applies the update X_{n+1} = U(Y, X_n). The formulations decide what Y is (all of X, or X
   with element stresses condensed out, or rotation increments), which TSTHETA cannot express.

   DESIGN.md §3 rule: of the TS this file writes only ptime, time_step, reason, vec_sol and
   the SNES (steps is advanced by PETSc's TSStep itself when reason >= 0, see
   src/ts/interface/ts.c of 3.18, so a type must not do it again). Everything else the type
   needs lives in TS_Rodmid. The SNES reaches the step problem through PETSc's generic
   SNESTSFormFunction/SNESTSFormJacobian, which call ts->ops->snesfunction/snesjacobian, the
   way PETSc's own implicit types are wired. */
#include <petsc/private/tsimpl.h>
#include <petsc/private/snesimpl.h> /* domainerror: a trial step may land in an invalid state */
#include "rs_rodmid.h"

typedef struct {
    /* The step problem, from TSRodmidSetStepProblem. */
    Vec            Y_template; /* layout of Y; NULL: X's layout */
    Mat            J;          /* kept for the whole run: one symbolic factorization */
    RsStepResidual residual;
    RsStepJacobian jacobian;
    RsStepVecFn    predictor;
    RsStepUpdate   update;
    void          *ctx;
    PetscInt       max_cutbacks;
    /* The feasible-step filter (TSRodmidSetAdmissible) and the Newton steps it shortened. */
    RsStepAdmissible admissible;
    /* The local error estimate of TSEvaluateWLTE (TSRodmidSetErrorEstimate), or NULL. */
    RsStepErrorEstimate estimate;
    void               *estimate_ctx;
    PetscInt         shortened;
    PetscInt         shortened_in_solve; /* Newton steps shortened in the current solve */
    /* Jacobian reuse (-ts_rodmid_reuse_jacobian): 0 is Newton's method, a new Jacobian at
       every iteration; a ratio in (0, 1) keeps the factored Jacobian across iterations and
       steps for as long as its full step cuts the residual norm at least by that ratio. */
    PetscReal reuse_ratio;
    PetscBool fresh;     /* the Jacobian was computed at the current Newton iterate */
    PetscInt  jacobians; /* Jacobians computed (and factored) over the run */
    /* Newton's stopping test with the rounding floor (SNESConverged_Rodmid). */
    Vec      rounding, rounding_image; /* u with u_i = +-eps |Y_i|, and J u */
    PetscInt  floor_steps;             /* accepted steps that ended at the floor, over the run */
    PetscBool at_floor;                /* the current solve ended at the floor */
    PetscReal fnorm_prev;              /* the residual norm of the previous iteration */
    /* Work vectors, created in TSSetUp_Rodmid. */
    Vec Y;  /* Newton unknown */
    Vec F;  /* residual */
    Vec X0; /* X_n: the callbacks read this copy, so a failed attempt cannot touch vec_sol */
    /* The attempt being solved: what the SNES callbacks pass to the step problem. */
    PetscReal t_n, h;
    /* The last accepted step. */
    PetscInt  last_its, last_cutbacks;
    PetscReal last_fnorm;
} TS_Rodmid;

static PetscErrorCode SNESTSFormFunction_Rodmid(SNES snes, Vec Y, Vec F, TS ts)
{
    TS_Rodmid *rm = (TS_Rodmid *)ts->data;

    PetscFunctionBegin;
    (void)snes;
    PetscCall(rm->residual(rm->t_n, rm->h, rm->X0, Y, F, rm->ctx));
    PetscFunctionReturn(0);
}

static PetscErrorCode SNESTSFormJacobian_Rodmid(SNES snes, Vec Y, Mat A, Mat B, TS ts)
{
    TS_Rodmid *rm = (TS_Rodmid *)ts->data;

    PetscFunctionBegin;
    (void)snes;
    ++rm->jacobians;
    rm->fresh = PETSC_TRUE;
    /* The step problem fills the matrix it owns; with -snes_mf_operator A is matrix-free and
       only needs an assembly to mark it current. */
    PetscCall(rm->jacobian(rm->t_n, rm->h, rm->X0, Y, B, rm->ctx));
    if (A != B) {
        PetscCall(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
        PetscCall(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
    }
    PetscFunctionReturn(0);
}

/* The reuse rule, a pre-check of the line search (so the line search, -snes_monitor and the
   convergence test are untouched). The SNES keeps its Jacobian (lag -1) and this decides, each
   iteration, whether the direction Y of the kept one may be used: its full step must cut the
   residual norm at least by the ratio. If not (or the trial state is invalid), the Jacobian
   is computed at the current iterate X and Y becomes Newton's direction; the line search then
   works on that as always. So a kept Jacobian is only ever used where it contracts fast
   (modified Newton near a solution), each new one costs a numeric factorization, the bulk of
   an iteration (docs/performance.md), and the solution is the same: the stopping test is the
   residual's. A rejected trial costs one residual and one triangular solve. */
static PetscErrorCode LineSearchPreCheck_RodmidReuse(SNESLineSearch linesearch, Vec X, Vec Y,
                                                     PetscBool *changed, void *ctx)
{
    TS_Rodmid *rm = (TS_Rodmid *)((TS)ctx)->data;
    SNES       snes;
    KSP        ksp;
    Mat        A, B;
    Vec        F, W, G;
    PetscReal  fnorm, gnorm;
    PetscBool  invalid;

    PetscFunctionBegin;
    *changed = PETSC_FALSE;
    if (rm->fresh) {
        rm->fresh = PETSC_FALSE; /* Newton's direction; from the next iteration on it is kept */
        PetscFunctionReturn(0);
    }
    PetscCall(SNESLineSearchGetSNES(linesearch, &snes));
    PetscCall(SNESLineSearchGetVecs(linesearch, NULL, &F, NULL, &W, &G));
    PetscCall(SNESLineSearchGetNorms(linesearch, NULL, &fnorm, NULL));
    PetscCall(VecWAXPY(W, -1.0, Y, X));
    PetscCall(SNESComputeFunction(snes, W, G));
    PetscCall(MPIU_Allreduce(&snes->domainerror, &invalid, 1, MPIU_BOOL, MPI_LOR,
                             PetscObjectComm((PetscObject)snes)));
    snes->domainerror = PETSC_FALSE; /* only the trial was invalid, not the iterate */
    if (!invalid) {
        PetscCall(VecNorm(G, NORM_2, &gnorm));
        if (gnorm <= rm->reuse_ratio * fnorm) PetscFunctionReturn(0); /* NaN fails the test */
    }
    PetscCall(SNESSetLagJacobian(snes, -2)); /* compute once, then keep (lag -1) */
    PetscCall(SNESGetJacobian(snes, &A, &B, NULL, NULL));
    PetscCall(SNESComputeJacobian(snes, X, A, B));
    PetscCall(SNESGetKSP(snes, &ksp));
    PetscCall(KSPSetOperators(ksp, A, B));
    PetscCall(KSPSolve(ksp, F, Y));
    rm->fresh = PETSC_FALSE;
    *changed  = PETSC_TRUE;
    PetscFunctionReturn(0);
}

/* The feasible-step filter (TSRodmidSetAdmissible): the Newton step Y (the iterate becomes
   X - lambda Y) is halved until X - Y is admissible, so the line search only sees admissible
   trial points of the full step. At most this many halvings (2^-30: a step far below any
   resolution); beyond, the line search meets the invalid state and the time step is cut.
   At most RODMID_MAX_SHORTENED Newton steps of one solve are shortened: an admissible set that
   holds Newton back step after step has the solution outside it (a load step that moves the
   rods further than contact's motion limit allows, the seven-wire strand stretched in two
   steps), and a smaller time step reaches it, where ever shorter Newton steps stalled until
   the iteration limit (measured: the strand's quasistatic stretch failed after 6 cut-backs of
   50 shortened iterations each; the thrown and dropped scenes shorten at most 5 per solve). */
#define RODMID_MAX_SHORTENINGS 30
#define RODMID_MAX_SHORTENED 8

/* The pre-check of the line search: the reuse rule (when on), then the filter (when set). */
static PetscErrorCode LineSearchPreCheck_Rodmid(SNESLineSearch linesearch, Vec X, Vec Y,
                                                PetscBool *changed, void *ctx)
{
    TS_Rodmid *rm = (TS_Rodmid *)((TS)ctx)->data;
    Vec        W;
    PetscBool  ok;
    PetscInt   halvings;

    PetscFunctionBegin;
    *changed = PETSC_FALSE;
    if (rm->reuse_ratio > 0.0) PetscCall(LineSearchPreCheck_RodmidReuse(linesearch, X, Y, changed, ctx));
    if (!rm->admissible || rm->shortened_in_solve >= RODMID_MAX_SHORTENED) PetscFunctionReturn(0);
    PetscCall(SNESLineSearchGetVecs(linesearch, NULL, NULL, NULL, &W, NULL));
    for (halvings = 0;; ++halvings) {
        PetscCall(VecWAXPY(W, -1.0, Y, X));
        PetscCall(rm->admissible(rm->t_n, rm->h, rm->X0, W, &ok, rm->ctx));
        if (ok || halvings == RODMID_MAX_SHORTENINGS) break;
        PetscCall(VecScale(Y, 0.5));
    }
    if (halvings > 0) {
        *changed = PETSC_TRUE;
        ++rm->shortened;
        ++rm->shortened_in_solve;
        PetscCall(PetscInfo(linesearch, "Newton step shortened by 2^-%" PetscInt_FMT " to stay admissible\n",
                            halvings));
    }
    PetscFunctionReturn(0);
}

/* The predictor under the feasible-step filter: a prediction the filter refuses (a thrown rod
   predicted into another) is pulled back towards the prediction of a zero step (h = 0: the
   state X_n itself, admissible as an accepted state) by halving, Y = Y_0 + 2^-k (Y_h - Y_0). */
static PetscErrorCode AdmissiblePrediction(TS ts)
{
    TS_Rodmid *rm = (TS_Rodmid *)ts->data;
    Vec        Y0 = rm->rounding, Yh = rm->rounding_image; /* free until the solve */
    PetscBool  ok;
    PetscInt   halvings;

    PetscFunctionBegin;
    PetscCall(rm->admissible(rm->t_n, rm->h, rm->X0, rm->Y, &ok, rm->ctx));
    if (ok) PetscFunctionReturn(0);
    PetscCall(VecCopy(rm->Y, Yh));
    PetscCall(rm->predictor(rm->t_n, 0.0, rm->X0, Y0, rm->ctx));
    {
        /* A prediction that does not depend on h (statics, the condensed step) has nothing to
           pull back: the solve meets the invalid state and the step is cut. */
        PetscBool same;
        PetscCall(VecEqual(Y0, Yh, &same));
        if (same) PetscFunctionReturn(0);
    }
    for (halvings = 1; halvings <= RODMID_MAX_SHORTENINGS; ++halvings) {
        PetscCall(VecWAXPY(rm->Y, PetscPowReal(0.5, (PetscReal)halvings), Yh, Y0));
        PetscCall(VecAXPY(rm->Y, -PetscPowReal(0.5, (PetscReal)halvings), Y0));
        PetscCall(rm->admissible(rm->t_n, rm->h, rm->X0, rm->Y, &ok, rm->ctx));
        if (ok) break;
    }
    if (!ok) {
        PetscCall(VecCopy(Y0, rm->Y));
        PetscCall(PetscInfo(ts, "prediction pulled back to X_n: none between was admissible\n"));
    } else {
        PetscCall(PetscInfo(ts, "prediction pulled back by 2^-%" PetscInt_FMT " to stay admissible\n",
                            halvings));
    }
    ++rm->shortened;
    PetscFunctionReturn(0);
}

/* The residual that rounding the unknowns to working precision makes: ||J u|| with
   u_i = +-eps |Y_i| (signs from a hash of the global index, so the same on any number of
   ranks). No iterate of Newton can get below it, because no closer iterate is representable:
   positions of a rod 30 km from the origin are only known to 7e-12 m, and the inertia rows
   turn that into residuals above the scenes' newton_atol (docs/stability.md, "The residual
   floor"). J is the last Jacobian computed, good enough for a size. */
static PetscErrorCode RoundingFloor(TS_Rodmid *rm, SNES snes, PetscReal *floor)
{
    const PetscScalar *y;
    PetscScalar       *u;
    PetscInt           lo, n, i;
    Vec                Y;
    Mat                J;

    PetscFunctionBegin;
    PetscCall(SNESGetSolution(snes, &Y));
    PetscCall(SNESGetJacobian(snes, &J, NULL, NULL, NULL));
    PetscCall(VecGetOwnershipRange(Y, &lo, NULL));
    PetscCall(VecGetLocalSize(Y, &n));
    PetscCall(VecGetArrayRead(Y, &y));
    PetscCall(VecGetArray(rm->rounding, &u));
    for (i = 0; i < n; ++i) {
        const unsigned long hash = ((unsigned long)(lo + i) * 2654435761UL) >> 13;
        u[i] = (hash & 1UL ? 1.0 : -1.0) * PETSC_MACHINE_EPSILON * PetscAbsScalar(y[i]);
    }
    PetscCall(VecRestoreArray(rm->rounding, &u));
    PetscCall(VecRestoreArrayRead(Y, &y));
    PetscCall(MatMult(J, rm->rounding, rm->rounding_image));
    PetscCall(VecNorm(rm->rounding_image, NORM_2, floor));
    PetscFunctionReturn(0);
}

/* Newton stagnating at the rounding floor: the residual norm is at most ||J u|| (and within
   a factor 1000 of atol, where the floor is worth a look). */
static PetscErrorCode AtRoundingFloor(TS_Rodmid *rm, SNES snes, PetscReal fnorm, PetscBool *at)
{
    PetscReal atol, floor;

    PetscFunctionBegin;
    *at = PETSC_FALSE;
    PetscCall(SNESGetTolerances(snes, &atol, NULL, NULL, NULL, NULL));
    if (!(fnorm <= 1e3 * atol)) PetscFunctionReturn(0);
    PetscCall(RoundingFloor(rm, snes, &floor));
    *at = (PetscBool)(fnorm <= floor);
    if (*at) PetscCall(PetscInfo(snes, "residual %g above atol %g but at the rounding floor %g\n",
                                 (double)fnorm, (double)atol, (double)floor));
    PetscFunctionReturn(0);
}

/* Newton's stopping test (DESIGN.md §3, §8): the residual norm at most newton_atol (PETSc's
   test, with the relative ones off), or Newton run to stagnation where that is out of reach:
   an iteration that did not halve the residual, which is at the rounding floor. Such a step
   is counted. (A line search that fails there is handled in TSStep_Rodmid.) */
static PetscErrorCode SNESConverged_Rodmid(SNES snes, PetscInt it, PetscReal xnorm,
                                           PetscReal snorm, PetscReal fnorm,
                                           SNESConvergedReason *reason, void *ctx)
{
    TS_Rodmid *rm = (TS_Rodmid *)((TS)ctx)->data;
    PetscReal  previous = rm->fnorm_prev;
    PetscBool  at;

    PetscFunctionBegin;
    rm->fnorm_prev = fnorm;
    if (it == 0) rm->at_floor = PETSC_FALSE;
    PetscCall(SNESConvergedDefault(snes, it, xnorm, snorm, fnorm, reason, NULL));
    if (*reason != SNES_CONVERGED_ITERATING || it == 0 || fnorm <= 0.5 * previous)
        PetscFunctionReturn(0);
    PetscCall(AtRoundingFloor(rm, snes, fnorm, &at));
    if (at) {
        *reason      = SNES_CONVERGED_SNORM_RELATIVE;
        rm->at_floor = PETSC_TRUE;
    }
    PetscFunctionReturn(0);
}

/* One step with bounded halving (DESIGN.md §3: "On SNES failure the step is halved and retried
   (bounded)"). Every attempt starts again from X_n and the predictor. */
static PetscErrorCode TSStep_Rodmid(TS ts)
{
    TS_Rodmid          *rm     = (TS_Rodmid *)ts->data;
    SNESConvergedReason reason = SNES_CONVERGED_ITERATING;
    PetscInt            cut;

    PetscFunctionBegin;
    PetscCall(VecCopy(ts->vec_sol, rm->X0));
    for (cut = 0;; ++cut) {
        rm->t_n = ts->ptime;
        rm->h   = ts->time_step;
        rm->shortened_in_solve = 0;
        if (rm->predictor) {
            PetscCall(rm->predictor(rm->t_n, rm->h, rm->X0, rm->Y, rm->ctx));
            if (rm->admissible) PetscCall(AdmissiblePrediction(ts));
        } else PetscCall(VecCopy(rm->X0, rm->Y));
        PetscCall(SNESSolve(ts->snes, NULL, rm->Y));
        PetscCall(SNESGetConvergedReason(ts->snes, &reason));
        if (reason > 0) {
            /* A solve without a Newton test (ksponly: se3_strand's one linear solve per step)
               "converges" to whatever the solve gives; a NaN or Inf there is a failed step,
               cut like any other, so no non-finite state is ever accepted and recorded
               (issue 21 item 20: NaN/Inf in the files of runs that failed at the first step). */
            PetscReal ynorm;
            PetscCall(VecNorm(rm->Y, NORM_INFINITY, &ynorm));
            if (!PetscIsInfOrNanReal(ynorm)) break;
            reason = SNES_DIVERGED_FNORM_NAN;
            PetscCall(SNESSetConvergedReason(ts->snes, reason));
        }
        if (reason == SNES_DIVERGED_LINE_SEARCH) {
            /* No descent left: if the iterate (a failed line search keeps it) is at the
               rounding floor, that is Newton run to stagnation, not a failure. */
            PetscReal fnorm;
            PetscCall(SNESGetFunctionNorm(ts->snes, &fnorm));
            PetscCall(AtRoundingFloor(rm, ts->snes, fnorm, &rm->at_floor));
            if (rm->at_floor) break;
        }
        PetscCall(
            PetscInfo(ts, "t = %g: SNES failed (%s) with h = %g after %" PetscInt_FMT " halvings\n",
                      (double)rm->t_n, SNESConvergedReasons[reason], (double)rm->h, cut));
        /* A new attempt starts from a new Jacobian (the kept one was made elsewhere). */
        if (rm->reuse_ratio > 0.0) PetscCall(SNESSetLagJacobian(ts->snes, -2));
        if (cut >= rm->max_cutbacks) {
            /* vec_sol still holds X_n: the caller writes the last good state. */
            ts->reason = TS_DIVERGED_NONLINEAR_SOLVE;
            PetscFunctionReturn(0);
        }
        ts->time_step *= 0.5;
    }
    PetscCall(SNESGetIterationNumber(ts->snes, &rm->last_its));
    PetscCall(SNESGetFunctionNorm(ts->snes, &rm->last_fnorm));
    rm->last_cutbacks = cut;
    if (rm->at_floor) ++rm->floor_steps;
    if (rm->update) PetscCall(rm->update(rm->t_n, rm->h, rm->X0, rm->Y, ts->vec_sol, rm->ctx));
    else PetscCall(VecCopy(rm->Y, ts->vec_sol));
    /* time_step stays the step taken; choosing the next one is the caller's business. */
    ts->ptime += rm->h;
    PetscFunctionReturn(0);
}

static PetscErrorCode TSSetUp_Rodmid(TS ts)
{
    TS_Rodmid *rm = (TS_Rodmid *)ts->data;
    PetscInt   n_x, n_y;
    PetscErrorCode (*jacobian)(SNES, Vec, Mat, Mat, void *) = NULL;

    PetscFunctionBegin;
    PetscCheck(rm->residual && rm->jacobian && rm->J, PetscObjectComm((PetscObject)ts),
               PETSC_ERR_ARG_WRONGSTATE,
               "TSRODMID needs its step problem: call TSRodmidSetStepProblem() before TSSetUp()");
    if (!rm->Y) PetscCall(VecDuplicate(rm->Y_template ? rm->Y_template : ts->vec_sol, &rm->Y));
    if (!rm->F) PetscCall(VecDuplicate(rm->Y, &rm->F));
    if (!rm->X0) PetscCall(VecDuplicate(ts->vec_sol, &rm->X0));
    if (!rm->rounding) PetscCall(VecDuplicate(rm->Y, &rm->rounding));
    if (!rm->rounding_image) PetscCall(VecDuplicate(rm->Y, &rm->rounding_image));
    PetscCall(VecGetSize(ts->vec_sol, &n_x));
    PetscCall(VecGetSize(rm->Y, &n_y));
    PetscCheck(n_x == n_y || (rm->predictor && rm->update), PetscObjectComm((PetscObject)ts),
               PETSC_ERR_ARG_INCOMP,
               "TSRODMID: Y has %" PetscInt_FMT " entries and X %" PetscInt_FMT
               "; the default predictor (Y = X_n) and update (X_{n+1} = Y) need equal sizes",
               n_y, n_x);

    PetscCall(TSGetSNES(ts, &ts->snes));
    PetscCall(SNESSetFunction(ts->snes, rm->F, SNESTSFormFunction, ts));
    /* Keep a Jacobian routine chosen through the options (-snes_fd); give it our matrix. */
    PetscCall(SNESGetJacobian(ts->snes, NULL, NULL, &jacobian, NULL));
    if (jacobian) PetscCall(SNESSetJacobian(ts->snes, rm->J, rm->J, NULL, NULL));
    else PetscCall(SNESSetJacobian(ts->snes, rm->J, rm->J, SNESTSFormJacobian, ts));
    PetscCall(SNESSetConvergenceTest(ts->snes, SNESConverged_Rodmid, ts, NULL));
    if (rm->reuse_ratio > 0.0) PetscCall(SNESSetLagJacobian(ts->snes, -2)); /* the first one is computed */
    /* The reuse rule and the feasible-step filter in one pre-check; it does nothing when
       neither is on (the filter may be set after TSSetUp). */
    {
        SNESLineSearch linesearch;
        PetscCall(SNESGetLineSearch(ts->snes, &linesearch));
        PetscCall(SNESLineSearchSetPreCheck(linesearch, LineSearchPreCheck_Rodmid, ts));
    }
    PetscFunctionReturn(0);
}

static PetscErrorCode TSReset_Rodmid(TS ts)
{
    TS_Rodmid *rm = (TS_Rodmid *)ts->data;

    PetscFunctionBegin;
    PetscCall(VecDestroy(&rm->Y));
    PetscCall(VecDestroy(&rm->F));
    PetscCall(VecDestroy(&rm->X0));
    PetscCall(VecDestroy(&rm->rounding));
    PetscCall(VecDestroy(&rm->rounding_image));
    PetscFunctionReturn(0);
}

static PetscErrorCode TSDestroy_Rodmid(TS ts)
{
    TS_Rodmid *rm = (TS_Rodmid *)ts->data;

    PetscFunctionBegin;
    PetscCall(TSReset_Rodmid(ts));
    PetscCall(VecDestroy(&rm->Y_template));
    PetscCall(MatDestroy(&rm->J));
    PetscCall(PetscFree(ts->data));
    PetscCall(PetscObjectComposeFunction((PetscObject)ts, "TSRodmidSetStepProblem_C", NULL));
    PetscCall(PetscObjectComposeFunction((PetscObject)ts, "TSRodmidSetMaxCutbacks_C", NULL));
    PetscCall(PetscObjectComposeFunction((PetscObject)ts, "TSRodmidGetMaxCutbacks_C", NULL));
    PetscCall(PetscObjectComposeFunction((PetscObject)ts, "TSRodmidGetStepStats_C", NULL));
    PetscCall(PetscObjectComposeFunction((PetscObject)ts, "TSRodmidGetRunStats_C", NULL));
    PetscCall(PetscObjectComposeFunction((PetscObject)ts, "TSRodmidSetAdmissible_C", NULL));
    PetscCall(PetscObjectComposeFunction((PetscObject)ts, "TSRodmidGetShortenedSteps_C", NULL));
    PetscCall(PetscObjectComposeFunction((PetscObject)ts, "TSRodmidSetErrorEstimate_C", NULL));
    PetscFunctionReturn(0);
}

static PetscErrorCode TSSetFromOptions_Rodmid(TS ts, PetscOptionItems *PetscOptionsObject)
{
    TS_Rodmid *rm = (TS_Rodmid *)ts->data;

    PetscFunctionBegin;
    PetscOptionsHeadBegin(PetscOptionsObject, "rodmid options (rodsolve's midpoint stepper)");
    PetscCall(PetscOptionsBoundedInt(
        "-ts_rodmid_max_cutbacks", "Halvings of one step before the TS fails",
        "TSRodmidSetMaxCutbacks", rm->max_cutbacks, &rm->max_cutbacks, NULL, 0));
    PetscCall(PetscOptionsReal(
        "-ts_rodmid_reuse_jacobian",
        "Keep the factored Jacobian while each Newton iteration cuts the residual by this ratio "
        "(0: a new Jacobian at every iteration)",
        "", rm->reuse_ratio, &rm->reuse_ratio, NULL));
    PetscCheck(rm->reuse_ratio >= 0.0 && rm->reuse_ratio < 1.0, PetscObjectComm((PetscObject)ts),
               PETSC_ERR_ARG_OUTOFRANGE, "-ts_rodmid_reuse_jacobian %g: the ratio must be in [0, 1)",
               (double)rm->reuse_ratio);
    PetscOptionsHeadEnd();
    PetscFunctionReturn(0);
}

static PetscErrorCode TSView_Rodmid(TS ts, PetscViewer viewer)
{
    TS_Rodmid *rm = (TS_Rodmid *)ts->data;
    PetscBool  ascii;

    PetscFunctionBegin;
    PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &ascii));
    if (ascii) {
        PetscCall(PetscViewerASCIIPrintf(
            viewer,
            "  rodmid: implicit midpoint on a user step problem, max cutbacks %" PetscInt_FMT
            ", Jacobian reuse ratio %g (%" PetscInt_FMT " Jacobians so far)\n",
            rm->max_cutbacks, (double)rm->reuse_ratio, rm->jacobians));
    }
    PetscFunctionReturn(0);
}

static PetscErrorCode TSRodmidSetStepProblem_Rodmid(TS ts, Vec Y_template, Mat J,
                                                    RsStepResidual residual,
                                                    RsStepJacobian jacobian, RsStepVecFn predictor,
                                                    RsStepUpdate update, void *ctx)
{
    TS_Rodmid *rm = (TS_Rodmid *)ts->data;

    PetscFunctionBegin;
    /* The work vectors and the SNES's matrices are made from these in TSSetUp. */
    PetscCheck(!ts->setupcalled, PetscObjectComm((PetscObject)ts), PETSC_ERR_ARG_WRONGSTATE,
               "TSRodmidSetStepProblem() must come before TSSetUp()");
    PetscCheck(residual && jacobian, PetscObjectComm((PetscObject)ts), PETSC_ERR_ARG_NULL,
               "TSRodmidSetStepProblem(): the residual and Jacobian routines are required");
    PetscCall(VecDestroy(&rm->Y_template));
    if (Y_template) PetscCall(VecDuplicate(Y_template, &rm->Y_template));
    PetscCall(PetscObjectReference((PetscObject)J));
    PetscCall(MatDestroy(&rm->J));
    rm->J         = J;
    rm->residual  = residual;
    rm->jacobian  = jacobian;
    rm->predictor = predictor;
    rm->update    = update;
    rm->ctx       = ctx;
    PetscFunctionReturn(0);
}

static PetscErrorCode TSRodmidSetAdmissible_Rodmid(TS ts, RsStepAdmissible admissible)
{
    TS_Rodmid *rm = (TS_Rodmid *)ts->data;

    PetscFunctionBegin;
    rm->admissible = admissible;
    PetscFunctionReturn(0);
}

static PetscErrorCode TSRodmidSetErrorEstimate_Rodmid(TS ts, RsStepErrorEstimate estimate, void *ctx)
{
    TS_Rodmid *rm = (TS_Rodmid *)ts->data;

    PetscFunctionBegin;
    rm->estimate     = estimate;
    rm->estimate_ctx = ctx;
    PetscFunctionReturn(0);
}

/* TSEvaluateWLTE: the caller's estimate (TSRodmidSetErrorEstimate), or none. */
static PetscErrorCode TSEvaluateWLTE_Rodmid(TS ts, NormType type, PetscInt *order, PetscReal *wlte)
{
    TS_Rodmid *rm = (TS_Rodmid *)ts->data;

    PetscFunctionBegin;
    *wlte = -1.0;
    if (rm->estimate) PetscCall(rm->estimate(ts, type, order, wlte, rm->estimate_ctx));
    PetscFunctionReturn(0);
}

static PetscErrorCode TSRodmidGetShortenedSteps_Rodmid(TS ts, PetscInt *shortened)
{
    TS_Rodmid *rm = (TS_Rodmid *)ts->data;

    PetscFunctionBegin;
    *shortened = rm->shortened;
    PetscFunctionReturn(0);
}

static PetscErrorCode TSRodmidSetMaxCutbacks_Rodmid(TS ts, PetscInt n)
{
    TS_Rodmid *rm = (TS_Rodmid *)ts->data;

    PetscFunctionBegin;
    PetscCheck(n >= 0, PetscObjectComm((PetscObject)ts), PETSC_ERR_ARG_OUTOFRANGE,
               "TSRodmidSetMaxCutbacks(): %" PetscInt_FMT " must be >= 0", n);
    rm->max_cutbacks = n;
    PetscFunctionReturn(0);
}

static PetscErrorCode TSRodmidGetMaxCutbacks_Rodmid(TS ts, PetscInt *n)
{
    TS_Rodmid *rm = (TS_Rodmid *)ts->data;

    PetscFunctionBegin;
    *n = rm->max_cutbacks;
    PetscFunctionReturn(0);
}

static PetscErrorCode TSRodmidGetStepStats_Rodmid(TS ts, PetscInt *newton_its, PetscInt *cutbacks,
                                                  PetscReal *fnorm)
{
    TS_Rodmid *rm = (TS_Rodmid *)ts->data;

    PetscFunctionBegin;
    if (newton_its) *newton_its = rm->last_its;
    if (cutbacks) *cutbacks = rm->last_cutbacks;
    if (fnorm) *fnorm = rm->last_fnorm;
    PetscFunctionReturn(0);
}

static PetscErrorCode TSRodmidGetRunStats_Rodmid(TS ts, PetscInt *jacobians, PetscInt *floor_steps)
{
    TS_Rodmid *rm = (TS_Rodmid *)ts->data;

    PetscFunctionBegin;
    if (jacobians) *jacobians = rm->jacobians;
    if (floor_steps) *floor_steps = rm->floor_steps;
    PetscFunctionReturn(0);
}

static PetscErrorCode TSCreate_Rodmid(TS ts)
{
    TS_Rodmid *rm;

    PetscFunctionBegin;
    PetscCall(PetscNew(&rm));
    rm->max_cutbacks = 6;
    ts->data         = (void *)rm;

    ts->ops->setup          = TSSetUp_Rodmid;
    ts->ops->step           = TSStep_Rodmid;
    ts->ops->reset          = TSReset_Rodmid;
    ts->ops->destroy        = TSDestroy_Rodmid;
    ts->ops->setfromoptions = TSSetFromOptions_Rodmid;
    ts->ops->view           = TSView_Rodmid;
    ts->ops->evaluatewlte   = TSEvaluateWLTE_Rodmid;
    ts->ops->snesfunction   = SNESTSFormFunction_Rodmid;
    ts->ops->snesjacobian   = SNESTSFormJacobian_Rodmid;
    ts->default_adapt_type  = TSADAPTNONE;
    ts->usessnes            = PETSC_TRUE;

    PetscCall(PetscObjectComposeFunction((PetscObject)ts, "TSRodmidSetStepProblem_C",
                                         TSRodmidSetStepProblem_Rodmid));
    PetscCall(PetscObjectComposeFunction((PetscObject)ts, "TSRodmidSetMaxCutbacks_C",
                                         TSRodmidSetMaxCutbacks_Rodmid));
    PetscCall(PetscObjectComposeFunction((PetscObject)ts, "TSRodmidGetMaxCutbacks_C",
                                         TSRodmidGetMaxCutbacks_Rodmid));
    PetscCall(PetscObjectComposeFunction((PetscObject)ts, "TSRodmidGetStepStats_C",
                                         TSRodmidGetStepStats_Rodmid));
    PetscCall(PetscObjectComposeFunction((PetscObject)ts, "TSRodmidGetRunStats_C",
                                         TSRodmidGetRunStats_Rodmid));
    PetscCall(PetscObjectComposeFunction((PetscObject)ts, "TSRodmidSetAdmissible_C",
                                         TSRodmidSetAdmissible_Rodmid));
    PetscCall(PetscObjectComposeFunction((PetscObject)ts, "TSRodmidGetShortenedSteps_C",
                                         TSRodmidGetShortenedSteps_Rodmid));
    PetscCall(PetscObjectComposeFunction((PetscObject)ts, "TSRodmidSetErrorEstimate_C",
                                         TSRodmidSetErrorEstimate_Rodmid));
    PetscFunctionReturn(0);
}

PetscErrorCode rs_rodmid_register(void)
{
    PetscErrorCode (*create)(TS) = NULL;

    PetscFunctionBegin;
    /* The list lives from TSInitializePackage to PetscFinalize: ask it, not a static flag. */
    PetscCall(TSInitializePackage());
    PetscCall(PetscFunctionListFind(TSList, TSRODMID, &create));
    if (!create) PetscCall(TSRegister(TSRODMID, TSCreate_Rodmid));
    PetscFunctionReturn(0);
}

PetscErrorCode TSRodmidSetStepProblem(TS ts, Vec Y_template, Mat J, RsStepResidual residual,
                                      RsStepJacobian jacobian, RsStepVecFn predictor,
                                      RsStepUpdate update, void *ctx)
{
    PetscFunctionBegin;
    PetscValidHeaderSpecific(ts, TS_CLASSID, 1);
    if (Y_template) PetscValidHeaderSpecific(Y_template, VEC_CLASSID, 2);
    PetscValidHeaderSpecific(J, MAT_CLASSID, 3);
    PetscTryMethod(
        ts, "TSRodmidSetStepProblem_C",
        (TS, Vec, Mat, RsStepResidual, RsStepJacobian, RsStepVecFn, RsStepUpdate, void *),
        (ts, Y_template, J, residual, jacobian, predictor, update, ctx));
    PetscFunctionReturn(0);
}

PetscErrorCode TSRodmidSetMaxCutbacks(TS ts, PetscInt n)
{
    PetscFunctionBegin;
    PetscValidHeaderSpecific(ts, TS_CLASSID, 1);
    PetscValidLogicalCollectiveInt(ts, n, 2);
    PetscTryMethod(ts, "TSRodmidSetMaxCutbacks_C", (TS, PetscInt), (ts, n));
    PetscFunctionReturn(0);
}

PetscErrorCode TSRodmidGetMaxCutbacks(TS ts, PetscInt *n)
{
    PetscFunctionBegin;
    PetscValidHeaderSpecific(ts, TS_CLASSID, 1);
    PetscValidIntPointer(n, 2);
    PetscUseMethod(ts, "TSRodmidGetMaxCutbacks_C", (TS, PetscInt *), (ts, n));
    PetscFunctionReturn(0);
}

PetscErrorCode TSRodmidGetStepStats(TS ts, PetscInt *newton_its, PetscInt *cutbacks,
                                    PetscReal *fnorm)
{
    PetscFunctionBegin;
    PetscValidHeaderSpecific(ts, TS_CLASSID, 1);
    PetscUseMethod(ts, "TSRodmidGetStepStats_C", (TS, PetscInt *, PetscInt *, PetscReal *),
                   (ts, newton_its, cutbacks, fnorm));
    PetscFunctionReturn(0);
}

PetscErrorCode TSRodmidGetRunStats(TS ts, PetscInt *jacobians, PetscInt *floor_steps)
{
    PetscFunctionBegin;
    PetscValidHeaderSpecific(ts, TS_CLASSID, 1);
    PetscUseMethod(ts, "TSRodmidGetRunStats_C", (TS, PetscInt *, PetscInt *),
                   (ts, jacobians, floor_steps));
    PetscFunctionReturn(0);
}

PetscErrorCode TSRodmidSetAdmissible(TS ts, RsStepAdmissible admissible)
{
    PetscFunctionBegin;
    PetscValidHeaderSpecific(ts, TS_CLASSID, 1);
    PetscTryMethod(ts, "TSRodmidSetAdmissible_C", (TS, RsStepAdmissible), (ts, admissible));
    PetscFunctionReturn(0);
}

PetscErrorCode TSRodmidSetErrorEstimate(TS ts, RsStepErrorEstimate estimate, void *ctx)
{
    PetscFunctionBegin;
    PetscValidHeaderSpecific(ts, TS_CLASSID, 1);
    PetscTryMethod(ts, "TSRodmidSetErrorEstimate_C", (TS, RsStepErrorEstimate, void *),
                   (ts, estimate, ctx));
    PetscFunctionReturn(0);
}

PetscErrorCode TSRodmidGetShortenedSteps(TS ts, PetscInt *shortened)
{
    PetscFunctionBegin;
    PetscValidHeaderSpecific(ts, TS_CLASSID, 1);
    PetscValidIntPointer(shortened, 2);
    PetscUseMethod(ts, "TSRodmidGetShortenedSteps_C", (TS, PetscInt *), (ts, shortened));
    PetscFunctionReturn(0);
}
