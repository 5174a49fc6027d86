/* The rodchain solver package: the chain LU (src/solver/chain_lu.c) behind PETSc's factor
   matrix interface (include/rs_rodchain.h), the way PETSc wires its external packages: a
   factor Mat of type "rodchain" whose symbolic, numeric and solve operations are ours, found
   by PCLU through MatSolverTypeRegister. */
#include <petsc/private/matimpl.h>
#include "rs_chain_lu.h"
#include "rs_rodchain.h"

/* A pattern whose panels would be larger than this is no chain worth dense panels (several
   coupled rods, a mechanism): MUMPS factors it. A rod's panels hold one element's unknowns
   (72 for ph_director's quadratic elements). */
#define RODCHAIN_LARGEST_PANEL 400

typedef struct {
    rs_chain_lu *forward;  /* the chain in the matrix's order */
    rs_chain_lu *backward; /* the same chain from its other end (made at the first need) */
    rs_chain_lu *active;   /* the one of the last factorization; NULL: the fallback's */
    rs_chain_lu *preferred; /* the direction that worked last */
    int         *order;    /* the chain order of `forward` (NULL: the matrix's own, ChainOrder) */
    Mat          A;        /* the matrix of the last factorization (referenced) */
    Mat          fallback; /* MUMPS, where neither direction could be factored */
    PetscReal    pivot_tol, check_tol, norm_A;
    PetscInt     replans; /* plans tried per chain after the first one */
    PetscBool    view, viewed, warned;
    PetscBool    checked;  /* the first solve after the factorization was checked */
    Vec          residual; /* work vector of that check */
    PetscInt     chain_count, fallback_count;
    PetscInt     since_failure; /* MUMPS factorizations since the chain last failed (0: it works) */
    PetscBool    not_a_chain;   /* the pattern has no chain structure worth the dense panels */
    PetscBool    no_backward;   /* the reversed pattern is no chain: only `forward` is tried */
    MatFactorInfo info;         /* of the last factorization, for a fallback inside a solve */
} Mat_RodChain;

/* MUMPS factors A for this factorization (DESIGN.md §3: a general sparse LU where the chain's
   structure does not hold); a matrix MUMPS cannot factor is reported, never solved. */
static PetscErrorCode FactorWithFallback(Mat F, Mat A, const MatFactorInfo *info, const char *why)
{
    Mat_RodChain  *rc = (Mat_RodChain *)F->data;
    MatFactorError error;

    PetscFunctionBegin;
    if (!rc->warned) {
        /* Said once per rod: such a rod runs at MUMPS's speed, and the user should know why. */
        PetscCall(PetscPrintf(PETSC_COMM_SELF,
                              "rodchain: %s; MUMPS factors such Jacobians of this rod (%s; said "
                              "once)\n",
                              why, rc->not_a_chain ? "all of them"
                                                   : "the chain is tried again after 1, 2, 4, "
                                                     "... of them"));
        rc->warned = PETSC_TRUE;
    }
    if (!rc->fallback) {
        PetscCall(MatGetFactor(A, MATSOLVERMUMPS, MAT_FACTOR_LU, &rc->fallback));
        PetscCall(MatLUFactorSymbolic(rc->fallback, A, NULL, NULL, info));
    }
    PetscCall(MatLUFactorNumeric(rc->fallback, A, info));
    PetscCall(MatFactorGetError(rc->fallback, &error));
    if (error) {
        F->factorerrortype             = error;
        F->factorerror_zeropivot_value = 0.0;
        F->factorerror_zeropivot_row   = 0;
    }
    rc->active = NULL;
    ++rc->fallback_count;
    ++rc->since_failure;
    PetscFunctionReturn(0);
}

/* ||b - A x||_inf <= check_tol (||A||_inf ||x||_inf + ||b||_inf): the normwise backward error
   of a solve, which partial pivoting inside panels cannot guarantee (a panel that is nearly
   singular on its own passes the pivot test with a large growth). */
static PetscErrorCode BackwardErrorOk(Mat_RodChain *rc, Vec b, Vec x, PetscBool *ok)
{
    PetscReal r, nx, nb;

    PetscFunctionBegin;
    if (!rc->residual) PetscCall(MatCreateVecs(rc->A, NULL, &rc->residual));
    PetscCall(MatMult(rc->A, x, rc->residual));
    PetscCall(VecAYPX(rc->residual, -1.0, b));
    PetscCall(VecNorm(rc->residual, NORM_INFINITY, &r));
    PetscCall(VecNorm(x, NORM_INFINITY, &nx));
    PetscCall(VecNorm(b, NORM_INFINITY, &nb));
    *ok = (PetscBool)(r <= rc->check_tol * (rc->norm_A * nx + nb));
    if (!*ok) PetscCall(PetscInfo(rc->A, "rodchain: backward error %g of the solve\n",
                                  (double)(r / (rc->norm_A * nx + nb))));
    PetscFunctionReturn(0);
}

static PetscErrorCode MatSolve_RodChain(Mat F, Vec b, Vec x)
{
    Mat_RodChain      *rc = (Mat_RodChain *)F->data;
    const PetscScalar *bb;
    PetscScalar       *xx;
    PetscBool          ok;

    PetscFunctionBegin;
    if (!rc->active) {
        PetscCall(MatSolve(rc->fallback, b, x));
        PetscFunctionReturn(0);
    }
    PetscCall(VecGetArrayRead(b, &bb));
    PetscCall(VecGetArray(x, &xx));
    rs_chain_lu_solve(rc->active, bb, xx);
    PetscCall(VecRestoreArray(x, &xx));
    PetscCall(VecRestoreArrayRead(b, &bb));
    if (rc->checked || rc->check_tol <= 0.0) PetscFunctionReturn(0);
    /* The first solve with a factorization shows whether it is backward stable; the same
       factors serve every later right-hand side (Jacobian reuse) unchecked. */
    rc->checked = PETSC_TRUE;
    PetscCall(BackwardErrorOk(rc, b, x, &ok));
    if (ok) PetscFunctionReturn(0);
    --rc->chain_count;
    rc->since_failure = 0;
    PetscCall(FactorWithFallback(F, rc->A, &rc->info, "a solve with the chain LU was not "
                                                      "backward stable (a panel nearly singular "
                                                      "on its own)"));
    if (F->factorerrortype) {
        /* Singular for MUMPS too: no solution, as PETSc marks a failed factorization (the
           Newton step is then invalid and the time step is cut). */
        PetscCall(VecSetInf(x));
        PetscFunctionReturn(0);
    }
    PetscCall(MatSolve(rc->fallback, b, x));
    PetscFunctionReturn(0);
}

/* Panels small enough for dense kernels (NULL: no chain at all). */
static PetscBool NarrowPanels(const rs_chain_lu *lu)
{
    rs_chain_lu_info chain;
    if (!lu) return PETSC_FALSE;
    rs_chain_lu_get_info(lu, &chain);
    return (PetscBool)(chain.largest_panel <= RODCHAIN_LARGEST_PANEL);
}

/* A chain order of a pattern that is a chain but not in its own order: a rod bordered by the
   multipliers of the ties at its ends, numbered after it (one rod's block of a bundle's block
   Jacobi, rs_system_rod_system: every tied end couples to the last rows, so the matrix's order
   has one panel of the whole rod). Breadth-first from the first unknown over the symmetrized
   pattern, the neighbours of each unknown in their order (Cuthill-McKee without the degree
   sort): the levels follow the rod's elements, and a tie's multipliers come in the level of the
   node they hold. Unknowns the search does not reach start a new search from the first of them.
   Returns 0, 2 (out of memory). */
static int ChainOrder(int n, const PetscInt *ia, const PetscInt *ja, int **result)
{
    int  *t_ptr  = calloc((size_t)n + 1, sizeof(int));
    int  *t_rows = malloc(((size_t)ia[n] + 1) * sizeof(int));
    int  *fill   = malloc(((size_t)n + 1) * sizeof(int));
    int  *order  = malloc((size_t)n * sizeof(int));
    char *seen = calloc((size_t)n, 1);
    int   head = 0, tail = 0, status = 0;

    *result = NULL;
    if (!t_ptr || !t_rows || !fill || !order || !seen) {
        status = 2;
        goto done;
    }
    /* The transposed pattern: who holds column j in its row. */
    for (int k = 0; k < ia[n]; ++k) ++t_ptr[ja[k] + 1];
    for (int j = 0; j < n; ++j) t_ptr[j + 1] += t_ptr[j];
    for (int j = 0; j <= n; ++j) fill[j] = t_ptr[j];
    for (int i = 0; i < n; ++i)
        for (PetscInt k = ia[i]; k < ia[i + 1]; ++k) t_rows[fill[ja[k]]++] = i;
    for (int first = 0; first < n; ++first) {
        if (seen[first]) continue;
        seen[first]    = 1;
        order[tail++]  = first;
        while (head < tail) {
            const int u = order[head++];
            /* Row u's columns and column u's rows, both sorted: merged in increasing order. */
            PetscInt a = ia[u], b = t_ptr[u];
            while (a < ia[u + 1] || b < t_ptr[u + 1]) {
                int v;
                if (b >= t_ptr[u + 1] || (a < ia[u + 1] && ja[a] <= t_rows[b])) {
                    v = (int)ja[a++];
                    if (b < t_ptr[u + 1] && t_rows[b] == v) ++b;
                } else {
                    v = t_rows[b++];
                }
                if (!seen[v]) {
                    seen[v]       = 1;
                    order[tail++] = v;
                }
            }
        }
    }
    *result = order;
    order   = NULL;
done:
    free(t_ptr);
    free(t_rows);
    free(fill);
    free(order);
    free(seen);
    return status;
}

/* The chain from its other end: the same panels problem on the reversed order. */
static PetscErrorCode BuildBackward(Mat_RodChain *rc, Mat A)
{
    const PetscInt *ia, *ja;
    PetscInt        n, *perm;
    PetscBool       done;
    int             status;

    PetscFunctionBegin;
    PetscCall(MatGetRowIJ(A, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
    PetscCheck(done, PETSC_COMM_SELF, PETSC_ERR_SUP, "rodchain: no CSR pattern of the matrix");
    PetscCall(PetscMalloc1(n, &perm));
    for (PetscInt p = 0; p < n; ++p) perm[p] = rc->order ? rc->order[n - 1 - p] : n - 1 - p;
    status = rs_chain_lu_symbolic_permuted((int)n, ia, ja, perm, &rc->backward);
    PetscCall(PetscFree(perm));
    PetscCall(MatRestoreRowIJ(A, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
    PetscCheck(status != 2, PETSC_COMM_SELF, PETSC_ERR_MEM, "rodchain: out of memory");
    /* A pattern that is a chain from its start need not be one from its end (the panels of
       the reversed order may exceed the limit): then MUMPS factors what the forward chain
       cannot, never a fatal error. */
    if (status) {
        rc->backward    = NULL;
        rc->no_backward = PETSC_TRUE;
        PetscCall(PetscInfo(rc->A, "rodchain: the reversed pattern is not a chain (status %d)\n",
                            status));
    }
    PetscFunctionReturn(0);
}

static PetscErrorCode ViewPanels(const rs_chain_lu *lu, const char *which)
{
    rs_chain_lu_info info;

    PetscFunctionBegin;
    rs_chain_lu_get_info(lu, &info);
    PetscCall(PetscPrintf(PETSC_COMM_SELF,
                          "rodchain (%s): %d panels, largest %d unknowns, coupling at most %d, "
                          "%.4g Mflop per factorization, %.4g MB\n",
                          which, info.n_panels, info.largest_panel, info.widest_coupling,
                          info.flops * 1e-6, info.doubles * 8e-6));
    PetscFunctionReturn(0);
}

/* Factor with `lu`; where a panel is singular on its own, plan the panels again without the
   cuts that failed (rs_chain_lu_replan: a constrained ph_director rod needs its cuts after the
   nodes), at most -mat_rodchain_replans times per chain over the run. *panel: 0, or the panel
   (1-based) that failed last. */
static PetscErrorCode FactorChain(Mat_RodChain *rc, rs_chain_lu *lu, const PetscScalar *values,
                                  int *panel)
{
    rs_chain_lu_info info;
    int              status;

    PetscFunctionBegin;
    for (;;) {
        *panel = rs_chain_lu_numeric(lu, values, (double)rc->pivot_tol);
        rs_chain_lu_get_info(lu, &info);
        if (!*panel || info.replans >= rc->replans) break;
        status = rs_chain_lu_replan(lu);
        PetscCheck(status != 2, PETSC_COMM_SELF, PETSC_ERR_MEM, "rodchain: out of memory");
        if (status) break;
        PetscCall(PetscInfo(rc->A, "rodchain: panel %d singular on its own, panels planned "
                                   "again\n", *panel));
    }
    PetscFunctionReturn(0);
}

/* Is the chain tried for this factorization? Always while it works; after it failed, at the
   1st, 2nd, 4th, 8th, ... factorization since (a failure may be one bad Newton iterate). */
static PetscBool TryChain(const Mat_RodChain *rc)
{
    const PetscInt since = rc->since_failure;
    return (PetscBool)(!rc->not_a_chain && (since & (since - 1)) == 0);
}

static PetscErrorCode MatLUFactorNumeric_RodChain(Mat F, Mat A, const MatFactorInfo *info)
{
    Mat_RodChain      *rc = (Mat_RodChain *)F->data;
    const PetscScalar *values;
    rs_chain_lu       *other;
    int                panel = 0;

    PetscFunctionBegin;
    F->factorerrortype = MAT_FACTOR_NOERROR;
    rc->active         = NULL;
    rc->checked        = PETSC_FALSE;
    rc->info           = *info;
    if (rc->A != A) {
        PetscCall(PetscObjectReference((PetscObject)A));
        PetscCall(MatDestroy(&rc->A));
        rc->A = A;
    }
    PetscCall(MatNorm(A, NORM_INFINITY, &rc->norm_A));
    if (TryChain(rc)) {
        PetscCall(MatSeqAIJGetArrayRead(A, &values));
        PetscCall(FactorChain(rc, rc->preferred, values, &panel));
        if (!panel) {
            rc->active = rc->preferred;
        } else {
            /* From the other end: a quasistatic rod whose first element floats is singular
               from the start of the chain and regular from its clamped end. */
            int other_panel;
            if (!rc->backward && !rc->no_backward) PetscCall(BuildBackward(rc, A));
            if (rc->backward) {
                other = rc->preferred == rc->forward ? rc->backward : rc->forward;
                PetscCall(FactorChain(rc, other, values, &other_panel));
                if (!other_panel) rc->active = rc->preferred = other;
            }
        }
        PetscCall(MatSeqAIJRestoreArrayRead(A, &values));
    }
    if (rc->active) {
        ++rc->chain_count;
        rc->since_failure = 0;
    } else {
        char why[160];
        if (panel) {
            PetscCall(PetscSNPrintf(why, sizeof(why),
                                    "panel %d of a Jacobian of this rod is singular on its own "
                                    "%s", panel, rc->no_backward ? "from the start of the chain "
                                    "(its reversed pattern is not a chain)" : "from either end "
                                    "of the chain"));
        } else if (rc->not_a_chain) {
            PetscCall(PetscSNPrintf(why, sizeof(why),
                                    "the Jacobian is not a chain (its panels would hold more than "
                                    "%d unknowns)", RODCHAIN_LARGEST_PANEL));
        } else {
            PetscCall(PetscStrcpy(why, "the chain failed before"));
        }
        PetscCall(FactorWithFallback(F, A, info, why));
    }
    if (rc->view && !rc->viewed && rc->active) {
        PetscCall(ViewPanels(rc->active, rc->active == rc->forward ? "from the start"
                                                                   : "from the end"));
        rc->viewed = PETSC_TRUE;
    }
    F->ops->solve = MatSolve_RodChain;
    PetscFunctionReturn(0);
}

static PetscErrorCode MatLUFactorSymbolic_RodChain(Mat F, Mat A, IS r, IS c,
                                                   const MatFactorInfo *info)
{
    Mat_RodChain   *rc = (Mat_RodChain *)F->data;
    const PetscInt *ia, *ja;
    PetscInt        n;
    PetscBool       done;
    int             status;

    PetscFunctionBegin;
    (void)r;
    (void)c;
    (void)info;
    rs_chain_lu_free(rc->forward);
    rs_chain_lu_free(rc->backward);
    rc->forward = rc->backward = rc->active = rc->preferred = NULL;
    free(rc->order);
    rc->order = NULL;
    PetscCall(MatDestroy(&rc->fallback));
    PetscCall(MatGetRowIJ(A, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
    PetscCheck(done, PETSC_COMM_SELF, PETSC_ERR_SUP, "rodchain: no CSR pattern of the matrix");
    status = rs_chain_lu_symbolic((int)n, ia, ja, &rc->forward);
    PetscCheck(status == 0 || status == 3, PETSC_COMM_SELF,
               status == 2 ? PETSC_ERR_MEM : PETSC_ERR_ARG_WRONG,
               "rodchain: the chain could not be set up from the pattern (status %d)", status);
    rc->not_a_chain = (PetscBool)(status == 3 || !NarrowPanels(rc->forward));
    if (rc->not_a_chain) {
        /* Not a chain in the matrix's order: perhaps in a chain order (ChainOrder). */
        rs_chain_lu *ordered = NULL;
        status = ChainOrder((int)n, ia, ja, &rc->order);
        PetscCheck(status == 0, PETSC_COMM_SELF, PETSC_ERR_MEM, "rodchain: out of memory");
        status = rs_chain_lu_symbolic_permuted((int)n, ia, ja, rc->order, &ordered);
        PetscCheck(status == 0 || status == 3, PETSC_COMM_SELF,
                   status == 2 ? PETSC_ERR_MEM : PETSC_ERR_ARG_WRONG,
                   "rodchain: the chain could not be set up from the pattern (status %d)", status);
        if (status == 0 && NarrowPanels(ordered)) {
            rs_chain_lu_free(rc->forward);
            rc->forward     = ordered;
            rc->not_a_chain = PETSC_FALSE;
        } else {
            rs_chain_lu_free(ordered);
            free(rc->order);
            rc->order = NULL;
        }
    }
    PetscCall(MatRestoreRowIJ(A, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
    rc->preferred = rc->forward;

    F->ops->lufactornumeric = MatLUFactorNumeric_RodChain;
    PetscFunctionReturn(0);
}

static PetscErrorCode MatGetInfo_RodChain(Mat F, MatInfoType flag, MatInfo *info)
{
    Mat_RodChain    *rc = (Mat_RodChain *)F->data;
    rs_chain_lu_info chain;

    PetscFunctionBegin;
    (void)flag;
    PetscCall(PetscMemzero(info, sizeof(*info)));
    info->block_size        = 1.0;
    info->fill_ratio_given  = 1.0;
    info->fill_ratio_needed = 1.0;
    if (rc->forward) {
        rs_chain_lu_get_info(rc->forward, &chain);
        info->nz_allocated = info->nz_used = chain.doubles;
        info->memory                       = 8.0 * chain.doubles;
    }
    PetscFunctionReturn(0);
}

static PetscErrorCode MatView_RodChain(Mat F, PetscViewer viewer)
{
    Mat_RodChain     *rc = (Mat_RodChain *)F->data;
    PetscBool         ascii;
    PetscViewerFormat format;
    rs_chain_lu_info  chain;

    PetscFunctionBegin;
    PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &ascii));
    if (!ascii) PetscFunctionReturn(0);
    PetscCall(PetscViewerGetFormat(viewer, &format));
    if (format != PETSC_VIEWER_ASCII_INFO) PetscFunctionReturn(0);
    if (rc->forward) {
        rs_chain_lu_get_info(rc->forward, &chain);
        PetscCall(PetscViewerASCIIPrintf(
            viewer,
            "rodchain: %d panels, largest %d, coupling at most %d, %.4g Mflop per "
            "factorization; %" PetscInt_FMT " chain factorizations, %" PetscInt_FMT
            " by MUMPS\n",
            chain.n_panels, chain.largest_panel, chain.widest_coupling, chain.flops * 1e-6,
            rc->chain_count, rc->fallback_count));
    }
    PetscFunctionReturn(0);
}

static PetscErrorCode MatDestroy_RodChain(Mat F)
{
    Mat_RodChain *rc = (Mat_RodChain *)F->data;

    PetscFunctionBegin;
    if (rc) {
        rs_chain_lu_free(rc->forward);
        rs_chain_lu_free(rc->backward);
        free(rc->order);
        PetscCall(MatDestroy(&rc->fallback));
        PetscCall(MatDestroy(&rc->A));
        PetscCall(VecDestroy(&rc->residual));
    }
    PetscCall(PetscFree(F->data));
    PetscCall(PetscObjectComposeFunction((PetscObject)F, "MatFactorGetSolverType_C", NULL));
    PetscFunctionReturn(0);
}

static PetscErrorCode MatFactorGetSolverType_RodChain(Mat F, MatSolverType *type)
{
    PetscFunctionBegin;
    (void)F;
    *type = MATSOLVERRODCHAIN;
    PetscFunctionReturn(0);
}

static PetscErrorCode MatGetFactor_seqaij_rodchain(Mat A, MatFactorType ftype, Mat *F)
{
    Mat           B;
    Mat_RodChain *rc;
    PetscInt      m, n;

    PetscFunctionBegin;
    PetscCheck(ftype == MAT_FACTOR_LU, PETSC_COMM_SELF, PETSC_ERR_SUP,
               "rodchain provides LU only");
    PetscCall(MatGetSize(A, &m, &n));
    PetscCheck(m == n, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "rodchain: the matrix must be square");
    PetscCall(MatCreate(PetscObjectComm((PetscObject)A), &B));
    PetscCall(MatSetSizes(B, PETSC_DECIDE, PETSC_DECIDE, m, n));
    PetscCall(PetscStrallocpy(MATSOLVERRODCHAIN, &((PetscObject)B)->type_name));
    PetscCall(MatSetUp(B));
    PetscCall(PetscNew(&rc));
    rc->pivot_tol = 1e-13;
    rc->check_tol = 1e-10;
    rc->replans   = 2;
    B->data       = rc;

    B->ops->lufactorsymbolic = MatLUFactorSymbolic_RodChain;
    B->ops->getinfo          = MatGetInfo_RodChain;
    B->ops->view             = MatView_RodChain;
    B->ops->destroy          = MatDestroy_RodChain;
    PetscCall(PetscObjectComposeFunction((PetscObject)B, "MatFactorGetSolverType_C",
                                         MatFactorGetSolverType_RodChain));
    B->factortype   = MAT_FACTOR_LU;
    B->assembled    = PETSC_TRUE;
    B->preallocated = PETSC_TRUE;
    /* The chain order is the matrix's: PCLU computes no ordering for it. */
    B->canuseordering = PETSC_FALSE;
    PetscCall(PetscFree(B->solvertype));
    PetscCall(PetscStrallocpy(MATSOLVERRODCHAIN, &B->solvertype));

    PetscOptionsBegin(PetscObjectComm((PetscObject)A), ((PetscObject)A)->prefix,
                      "rodchain: the chain LU of one rod", "Mat");
    PetscCall(PetscOptionsReal("-mat_rodchain_pivot_tol",
                               "A pivot below this times its column's largest entry is zero",
                               "", rc->pivot_tol, &rc->pivot_tol, NULL));
    PetscCall(PetscOptionsReal("-mat_rodchain_check_tol",
                               "Largest normwise backward error of the first solve with a "
                               "factorization before MUMPS factors it instead",
                               "", rc->check_tol, &rc->check_tol, NULL));
    PetscCall(PetscOptionsBoundedInt("-mat_rodchain_replans",
                                     "Plans of the panels tried after one with a singular panel",
                                     "", rc->replans, &rc->replans, NULL, 0));
    PetscCall(PetscOptionsBool("-mat_rodchain_view", "Print the panels at the first factorization",
                               "", rc->view, &rc->view, NULL));
    PetscOptionsEnd();
    *F = B;
    PetscFunctionReturn(0);
}

PetscErrorCode rs_rodchain_register(void)
{
    PetscFunctionBegin;
    /* The built-in packages (MUMPS, the fallback) are registered by the package's
       initialization; registering first would leave them out. */
    PetscCall(MatInitializePackage());
    PetscCall(MatSolverTypeRegister(MATSOLVERRODCHAIN, MATSEQAIJ, MAT_FACTOR_LU,
                                    MatGetFactor_seqaij_rodchain));
    PetscFunctionReturn(0);
}

PetscErrorCode rs_rodchain_get_stats(Mat F, PetscInt *chain, PetscInt *fallback)
{
    MatSolverType type = NULL;
    PetscBool     ours;

    PetscFunctionBegin;
    PetscCall(MatFactorGetSolverType(F, &type));
    PetscCall(PetscStrcmp(type, MATSOLVERRODCHAIN, &ours));
    PetscCheck(ours, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "not a rodchain factor");
    if (chain) *chain = ((Mat_RodChain *)F->data)->chain_count;
    if (fallback) *fallback = ((Mat_RodChain *)F->data)->fallback_count;
    PetscFunctionReturn(0);
}
