/* The modes of a linear pencil P(s) = a0 + s a1 + s^2 a2 with SLEPc (issue 27 item 1,
   docs/theory/modes.md): rodsolve's one door to SLEPc, called from Fortran through bind(C)
   (src/solver/modal_solver.F90). The pencil comes as one CSR pattern with three value
   arrays, whole on every rank; each rank inserts its share of the rows into PETSc matrices on
   PETSC_COMM_WORLD, so the eigen solve (and MUMPS's factorization) is distributed.

   The problem solved is a generalized eigenproblem Op0 x = mu Op1 x:
     degree 1 (a2 = 0; the first-order form B x' + A x = 0): Op0 = a0, Op1 = a1, mu = -s;
     degree 2 with a1 = 0 (undamped, M q'' + K q = 0): Op0 = a0, Op1 = a2, mu = -s^2 = omega^2.
   Both are non-Hermitian in general (constraint rows, se3_pg's rotation rows in the body
   basis), and Op1 is singular (algebraic rows), so EPS_GNHEP with shift-and-invert: the shift
   sigma is real and negative, and the eigenvalues wanted are +-i omega (degree 1) or omega^2
   >= 0 (degree 2), so |mu - sigma| grows with omega for either: the eigenvalues nearest the
   target (EPS_TARGET_MAGNITUDE's order, with ties: compare_nearest) are the lowest modes in
   order, and a0 - sigma a1 is regular even when a0 is singular (the rigid modes of a free
   rod). The caller passes the pencil equilibrated (src/solver/modal_solver.F90). The
   factorization is MUMPS's LU (KSPPREONLY, PCLU): the pencils have multipliers and are
   indefinite (DESIGN.md §3). Options with the prefix -modes_ override.

   Floating-point traps and PETSc error messages are handled as in rod_stepper.c. */
#include <slepceps.h>
#include <fenv.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include "rs_petsc_error_capture.h"


/* A matrix on PETSC_COMM_WORLD from the rows [lo, hi) of the whole CSR pattern. */
static PetscErrorCode pencil_matrix(PetscInt n, PetscInt lo, PetscInt hi, const int *row_ptr,
                                    const int *cols, const double *values, Mat *A)
{
    PetscInt *ii, *jj, nnz = row_ptr[hi] - row_ptr[lo];
    PetscScalar *vv;
    PetscFunctionBeginUser;
    PetscCall(PetscMalloc3(hi - lo + 1, &ii, nnz, &jj, nnz, &vv));
    for (PetscInt i = lo; i <= hi; i++) ii[i - lo] = row_ptr[i] - row_ptr[lo];
    for (PetscInt k = 0; k < nnz; k++) {
        jj[k] = cols[row_ptr[lo] + k];
        vv[k] = values[row_ptr[lo] + k];
    }
    PetscCall(MatCreate(PETSC_COMM_WORLD, A));
    PetscCall(MatSetSizes(*A, hi - lo, hi - lo, n, n));
    PetscCall(MatSetType(*A, MATAIJ));
    PetscCall(MatSeqAIJSetPreallocationCSR(*A, ii, jj, vv));
    PetscCall(MatMPIAIJSetPreallocationCSR(*A, ii, jj, vv));
    PetscCall(PetscFree3(ii, jj, vv));
    PetscFunctionReturn(0);
}

/* The whole of a distributed vector on every rank, into `out` (n values). */
static PetscErrorCode gather_whole(Vec v, double *out)
{
    VecScatter scatter;
    Vec all;
    const PetscScalar *a;
    PetscInt n;
    PetscFunctionBeginUser;
    PetscCall(VecScatterCreateToAll(v, &scatter, &all));
    PetscCall(VecScatterBegin(scatter, v, all, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(scatter, v, all, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecGetSize(all, &n));
    PetscCall(VecGetArrayRead(all, &a));
    for (PetscInt i = 0; i < n; i++) out[i] = PetscRealPart(a[i]);
    PetscCall(VecRestoreArrayRead(all, &a));
    PetscCall(VecScatterDestroy(&scatter));
    PetscCall(VecDestroy(&all));
    PetscFunctionReturn(0);
}

/* MUMPS's settings for the shift-and-invert factorization, below any -modes_st_mat_mumps_*
   option given: AMD ordering and a 400% work-space margin, as rod_stepper.c gives a distributed
   matrix (MUMPS does not permute large entries onto the diagonal of distributed input, and
   the zero diagonal of the multiplier rows delays pivots: a 50% margin failed with INFOG(1) =
   -9 on the ph_director cantilever on 2 ranks), the relative pivot threshold 0.01 on any
   number of ranks, so that 1 and 2 ranks factor alike. */
static PetscErrorCode mumps_defaults(void)
{
    const char *names[] = {"-modes_st_mat_mumps_icntl_14", "-modes_st_mat_mumps_icntl_7",
                           "-modes_st_mat_mumps_cntl_1"};
    const char *values[] = {"400", "0", "0.01"};
    PetscBool given;
    PetscFunctionBeginUser;
    for (int i = 0; i < 3; i++) {
        PetscCall(PetscOptionsHasName(NULL, NULL, names[i], &given));
        if (!given) PetscCall(PetscOptionsSetValue(NULL, names[i], values[i]));
    }
    PetscFunctionReturn(0);
}

/* Eigenvalues whose distances from the target agree to this share are ties (compare_nearest). */
static const PetscReal tie_share = 1.0e-6;

/* EPS_TARGET_MAGNITUDE with ties: a before b (-1), after it (1), or a tie (0) when their
   distances from the target agree to tie_share, so that SLEPc's sorting keeps tied Ritz values
   in the order of their Schur form. With the plain comparison, the selection sort of the
   projected problem (DSSort_NHEP_Total) moved one member of a degenerate bending pair of the
   circular section (two 2 x 2 blocks with equal eigenvalues when the pencil is equilibrated,
   src/solver/modal_solver.F90) past the other whenever round-off put it nearer the target, and
   LAPACK's trexc refused that swap (info = 1: the blocks are too close for a stable swap),
   which stopped the solve: seed 004's 1 m tube with OpenBLAS's Sandybridge kernels, a free
   ph_director rod's cluster of rigid-body modes with one of the equilibration weights tried.
   On that tube ties up to 1e-12 still failed and 1e-10 passed; with 1e-6 none of 120 solves
   failed (the tube at five lengths, free rods of 10 - 40 elements, the damped and output
   cases of tests/regression/modes/modes.py; four OpenBLAS kernels, three MUMPS orderings),
   one did without ties. 1e-6 leaves room for Ritz values not yet converged. The converged
   pairs are then put in the strict order (strict_order), so that a pair split by more than
   round-off keeps its order (se3_pg's Euler column: its two bending planes' load factors 7e-8
   apart with OpenBLAS's SkylakeX kernels, the quasistatic state not exactly symmetric). */
static PetscErrorCode compare_nearest(PetscScalar ar, PetscScalar ai, PetscScalar br,
                                      PetscScalar bi, PetscInt *result, void *ctx)
{
    const PetscScalar target = *(const PetscScalar *)ctx;
    const PetscReal a = SlepcAbsEigenvalue(ar - target, ai);
    const PetscReal b = SlepcAbsEigenvalue(br - target, bi);
    PetscFunctionBeginUser;
    if (PetscAbsReal(a - b) <= tie_share * PetscMax(a, b)) *result = 0;
    else *result = a > b ? 1 : -1;
    PetscFunctionReturn(0);
}

/* The converged eigenpairs of eps in order of their distance from the target, nearest first,
   a complex conjugate pair (adjacent in SLEPc's order) kept together and in its order:
   order[k] is the index for EPSGetEigenpair of the k-th (nconv entries, allocated here). */
static PetscErrorCode strict_order(EPS eps, PetscInt nconv, PetscScalar target, PetscInt **order)
{
    PetscReal *distance;
    PetscInt *size, n_units = 0;
    PetscFunctionBeginUser;
    PetscCall(PetscMalloc1(nconv, order));
    PetscCall(PetscMalloc2(nconv, &distance, nconv, &size));
    /* units: a real eigenvalue, or a conjugate pair (its first index, size 2) */
    for (PetscInt i = 0; i < nconv; i++) {
        PetscScalar kr, ki;
        PetscCall(EPSGetEigenvalue(eps, i, &kr, &ki));
        (*order)[n_units] = i;
        distance[n_units] = SlepcAbsEigenvalue(kr - target, ki);
        size[n_units] = (PetscRealPart(ki) != 0.0 && i + 1 < nconv) ? 2 : 1;
        i += size[n_units] - 1;
        n_units++;
    }
    /* insertion sort of the units, stable */
    for (PetscInt u = 1; u < n_units; u++) {
        PetscInt first = (*order)[u], width = size[u], v = u;
        PetscReal d = distance[u];
        while (v > 0 && distance[v - 1] > d) {
            (*order)[v] = (*order)[v - 1];
            distance[v] = distance[v - 1];
            size[v] = size[v - 1];
            v--;
        }
        (*order)[v] = first;
        distance[v] = d;
        size[v] = width;
    }
    /* expand the units into eigenpair indices, from the back so as not to overwrite */
    {
        PetscInt k = nconv;
        for (PetscInt u = n_units - 1; u >= 0; u--) {
            const PetscInt first = (*order)[u];
            for (PetscInt j = size[u] - 1; j >= 0; j--) (*order)[--k] = first + j;
        }
    }
    PetscCall(PetscFree2(distance, size));
    PetscFunctionReturn(0);
}

static PetscErrorCode solve(int n, const int *row_ptr, const int *cols, const double *a0,
                            const double *a1, const double *a2, int degree, int n_wanted,
                            double shift, int *n_found, double *mu_re, double *mu_im,
                            double *vec_re, double *vec_im, double *errors, char *solver_text,
                            int text_len)
{
    Mat A, B;
    EPS eps;
    ST st;
    KSP ksp;
    PC pc;
    Vec xr, xi;
    PetscInt lo = PETSC_DECIDE, hi, local = PETSC_DECIDE, nconv, nn = n, *order;
    PetscBool initialized;
    MPI_Comm comm = PETSC_COMM_WORLD;
    EPSType type;
    MatSolverType package;
    PetscScalar target;
    PetscFunctionBeginUser;
    PetscCall(SlepcInitialized(&initialized));
    if (!initialized) PetscCall(SlepcInitializeNoArguments());
    PetscCall(PetscSplitOwnership(comm, &local, &nn));
    PetscCallMPI(MPI_Scan(&local, &hi, 1, MPIU_INT, MPI_SUM, comm));
    lo = hi - local;
    PetscCall(pencil_matrix(n, lo, hi, row_ptr, cols, a0, &A));
    PetscCall(pencil_matrix(n, lo, hi, row_ptr, cols, degree == 1 ? a1 : a2, &B));

    PetscCall(EPSCreate(comm, &eps));
    PetscCall(EPSSetOperators(eps, A, B));
    PetscCall(EPSSetProblemType(eps, EPS_GNHEP));
    PetscCall(EPSSetType(eps, EPSKRYLOVSCHUR));
    target = shift;
    PetscCall(EPSSetWhichEigenpairs(eps, EPS_WHICH_USER));
    PetscCall(EPSSetEigenvalueComparison(eps, compare_nearest, &target));
    PetscCall(EPSSetTarget(eps, shift));
    PetscCall(EPSSetDimensions(eps, n_wanted, PETSC_DEFAULT, PETSC_DEFAULT));
    PetscCall(EPSSetTolerances(eps, 1.0e-14, 500));
    PetscCall(EPSGetST(eps, &st));
    PetscCall(STSetType(st, STSINVERT));
    PetscCall(STGetKSP(st, &ksp));
    PetscCall(KSPSetType(ksp, KSPPREONLY));
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PCSetType(pc, PCLU));
    PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
    PetscCall(EPSSetOptionsPrefix(eps, "modes_"));
    PetscCall(mumps_defaults());
    PetscCall(EPSSetFromOptions(eps));
    PetscCall(EPSSolve(eps));
    PetscCall(EPSGetConverged(eps, &nconv));
    PetscCall(EPSGetType(eps, &type));
    PetscCall(PCFactorGetMatSolverType(pc, &package));
    snprintf(solver_text, (size_t)text_len, "SLEPc EPS %s, shift-and-invert at %.3g, LU by %s",
             type, shift, package ? package : "petsc");

    *n_found = nconv < n_wanted ? (int)nconv : n_wanted;
    PetscCall(strict_order(eps, nconv, target, &order));
    PetscCall(MatCreateVecs(A, &xr, NULL));
    PetscCall(VecDuplicate(xr, &xi));
    for (int i = 0; i < *n_found; i++) {
        PetscScalar kr, ki;
        PetscReal error;
        PetscCall(EPSGetEigenpair(eps, order[i], &kr, &ki, xr, xi));
        /* The backward error |r| / ((|A| + |mu| |B|) |x|): the relative one divides by |mu|,
           which is round-off at a rigid-body zero (1e1 - 1e2 at se3_strand's exact zeros). */
        PetscCall(EPSComputeError(eps, order[i], EPS_ERROR_BACKWARD, &error));
        mu_re[i] = PetscRealPart(kr);
        mu_im[i] = PetscRealPart(ki);
        errors[i] = error;
        PetscCall(gather_whole(xr, vec_re + (size_t)i * n));
        PetscCall(gather_whole(xi, vec_im + (size_t)i * n));
    }
    PetscCall(PetscFree(order));
    PetscCall(VecDestroy(&xr));
    PetscCall(VecDestroy(&xi));
    PetscCall(EPSDestroy(&eps));
    PetscCall(MatDestroy(&A));
    PetscCall(MatDestroy(&B));
    PetscFunctionReturn(0);
}

/* Modes of the pencil (see the file header): up to n_wanted eigenpairs nearest the shift,
   eigenvalues mu = mu_re + i mu_im, eigenvectors (n each, whole on every rank) in vec_re,
   vec_im, backward errors in errors. Collective on PETSC_COMM_WORLD. Returns 0, or an
   error with a message. */
int rs_modes_solve(int n, const int *row_ptr, const int *cols, const double *a0,
                   const double *a1, const double *a2, int degree, int n_wanted, double shift,
                   int *n_found, double *mu_re, double *mu_im, double *vec_re, double *vec_im,
                   double *errors, char *solver_text, int text_len, char *errmsg, int errlen)
{
    RsErrorCapture capture = {{0}, 0};
    fenv_t caller_env;
    PetscErrorCode ierr;
    *n_found = 0;
    if (errmsg && errlen > 0) errmsg[0] = '\0';
    feholdexcept(&caller_env);
    PetscPushErrorHandler(rs_capture_petsc_error, &capture);
    ierr = solve(n, row_ptr, cols, a0, a1, a2, degree, n_wanted, shift, n_found, mu_re, mu_im,
                 vec_re, vec_im, errors, solver_text, text_len);
    PetscPopErrorHandler();
    fesetenv(&caller_env);
    if (ierr) {
        if (capture.have) snprintf(errmsg, (size_t)errlen, "SLEPc eigen solve: %s", capture.text);
        else snprintf(errmsg, (size_t)errlen, "SLEPc eigen solve: PETSc error %d", (int)ierr);
        return (int)ierr;
    }
    return 0;
}

/* SLEPc's version, "3.18.2". */
void rs_slepc_version(char *buffer, int length)
{
    snprintf(buffer, (size_t)length, "%d.%d.%d", SLEPC_VERSION_MAJOR, SLEPC_VERSION_MINOR,
             SLEPC_VERSION_SUBMINOR);
}

/* SlepcFinalize when the modes started SLEPc (PETSc's own finalize follows it). */
int rs_slepc_finalize(void)
{
    PetscBool initialized = PETSC_FALSE, finalized = PETSC_FALSE;
    SlepcInitialized(&initialized);
    SlepcFinalized(&finalized);
    if (initialized && !finalized) return (int)SlepcFinalize();
    return 0;
}
