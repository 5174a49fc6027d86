/* Unit tests of the rodchain solver package (include/rs_rodchain.h, src/solver/rodchain.c):
   the chain LU behind PCLU, sequential, on random matrices with the pattern of a rod's Jacobian
   (nodes and element interiors along the rod, dense random blocks, node multipliers with a zero
   diagonal; a reduced copy of the generator of test_chain_lu.c).

   Checked: a KSP (preonly, PCLU, "rodchain") solves as MUMPS does, and the options database
   still selects either package over the one set in code; a matrix whose first panel is singular
   is factored from the other end of the chain, one singular from both ends by MUMPS, and one
   whose first panel is only nearly singular (the chain passes its pivot test, with a large
   backward error) by MUMPS after the check of the first solve, each time with the right
   solution and counted in rs_rodchain_get_stats; a singular matrix fails the PC
   (KSP_DIVERGED_PC_FAILED) without a finite "solution", and the next regular matrix is
   factored by the chain again; after a failure, the chain is tried at the 1st, 2nd, 4th, ...
   factorization as its message says; one factorization serves several right-hand sides and a
   second factorization new values of the same pattern.

   Floating-point traps are off here (a C main program), as inside the stepper's PETSc calls
   (src/solver/rod_stepper.c): PETSc's VecSetInf divides by zero on purpose.

   Bookkeeping as in tests/support/assert.F90: a test passes when none of its checks failed,
   failures go to standard error as file:line: test: message, and the last line is
   "N passed, M failed" (exit status 1 if any failed). Achieved values go to standard output. */
#include <petscksp.h>

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rs_chain_lu.h"
#include "dense_reference.h"
#include "rs_rodchain.h"

/* LAPACK (the dense reference). */

/* ---- Bookkeeping (tests/support/assert.F90) ---------------------------------------------- */

static int         n_passed, n_failed, failures_in_current;
static const char *current_test = "";

static void check_at(int ok, const char *file, int line, const char *format, ...)
{
    va_list args;

    if (ok) return;
    ++failures_in_current;
    fflush(stdout);
    fprintf(stderr, "%s:%d: %s: expected true: ", file, line, current_test);
    va_start(args, format);
    vfprintf(stderr, format, args);
    va_end(args);
    fputc('\n', stderr);
}

/* Fails unless cond holds; the message is a printf format. */
#define CHECK(cond, ...) check_at((cond) != 0, __FILE__, __LINE__, __VA_ARGS__)

/* Prints what a check achieved and fails unless achieved <= bound (NaN fails). */
#define CHECK_BELOW(achieved, bound, what) \
    check_below_at((achieved), (bound), (what), __FILE__, __LINE__)

static void check_below_at(double achieved, double bound, const char *what, const char *file,
                           int line)
{
    printf("    %-58s %10.3e (bound %9.2e)\n", what, achieved, bound);
    check_at(achieved <= bound, file, line, "%s: %.3e <= %.2e", what, achieved, bound);
}

/* A test is a PetscErrorCode function; a PETSc error in it is a failure of the test. */
static void run_test(const char *name, PetscErrorCode (*test)(void))
{
    PetscErrorCode error;

    current_test        = name;
    failures_in_current = 0;
    error               = test();
    check_at(error == 0, __FILE__, __LINE__, "no PETSc error, got %d", (int)error);
    if (failures_in_current == 0) {
        ++n_passed;
        printf("[  PASSED  ] %s\n", name);
    } else {
        ++n_failed;
        printf("[  FAILED  ] %s (%d failed assertions)\n", name, failures_in_current);
    }
    fflush(stdout);
}

/* ---- What the package prints: its lines are counted (PetscPrintf goes through here) ----- */

static PetscErrorCode (*petsc_vfprintf)(FILE *, const char[], va_list);
static int fallback_lines;

static PetscErrorCode counting_vfprintf(FILE *file, const char format[], va_list args)
{
    char    line[512];
    va_list copy;

    va_copy(copy, args);
    vsnprintf(line, sizeof(line), format, copy);
    va_end(copy);
    if (strstr(line, "rodchain:") && strstr(line, "MUMPS factors")) ++fallback_lines;
    return petsc_vfprintf(file, format, args);
}

/* ---- Random numbers: a fixed-seed LCG (Knuth's MMIX constants), so every run is the same -- */




/* ---- Rod-like matrices (as in test_chain_lu.c) ------------------------------------------- */

/* Unknowns along the rod: node 0, interior 0, node 1, ..., interior E-1, node E. The last
   unknown of every node is a multiplier: coupled only to the node's other unknowns, zero
   diagonal. Constraint rows of element 0 (at the end of its interior) couple to its interior
   and to node 1 only, with interior parts equal up to `constraint_gap`: the panel of node 0 and
   interior 0 is singular (gap 0) or nearly so, the matrix is not, and from the other end of the
   chain (node 1 eliminated with interior 0) it factors. Element E-1 can have the mirror image.
   `mass` (M / h^2 of a dynamic rod) on the diagonal of the other unknowns keeps the panels
   about as well conditioned as the matrix. */
typedef struct {
    int    n_elements, node_size, interior_size;
    int    first_constraints, last_constraints;
    double constraint_gap, mass;
} rod_shape_t;


static int node_start(const rod_shape_t *s, int e)
{
    return e * (s->node_size + s->interior_size);
}

static void set_block(rod_matrix_t *m, const int *rows, int n_rows, const int *cols, int n_cols)
{
    for (int j = 0; j < n_cols; ++j)
        for (int i = 0; i < n_rows; ++i) {
            m->a[rows[i] + (size_t)cols[j] * m->n]      = lcg_uniform();
            m->stored[rows[i] + (size_t)cols[j] * m->n] = 1;
        }
}

/* The node's unknowns but its multiplier (the last). */
static int node_primal(const rod_shape_t *s, int e, int *list)
{
    for (int k = 0; k < s->node_size - 1; ++k) list[k] = node_start(s, e) + k;
    return s->node_size - 1;
}


static void rod_matrix_make(const rod_shape_t *s, uint64_t seed, rod_matrix_t *m)
{
    const int n = node_start(s, s->n_elements) + s->node_size;
    int      *p0 = malloc((size_t)n * sizeof(int)), *p1 = malloc((size_t)n * sizeof(int));
    int      *inner = malloc((size_t)n * sizeof(int)), *lambda = malloc((size_t)n * sizeof(int));
    double   *shared = malloc((size_t)n * sizeof(double));

    lcg_seed(seed);
    m->n      = n;
    m->a      = calloc((size_t)n * n, sizeof(double));
    m->stored = calloc((size_t)n * n, 1);
    for (int e = 0; e <= s->n_elements; ++e) {
        const int np = node_primal(s, e, p0), multiplier = node_start(s, e) + np;
        set_block(m, p0, np, p0, np);
        set_block(m, &multiplier, 1, p0, np);
        set_block(m, p0, np, &multiplier, 1);
    }
    for (int e = 0; e < s->n_elements; ++e) {
        const int np0 = node_primal(s, e, p0), np1 = node_primal(s, e + 1, p1);
        const int first = node_start(s, e) + s->node_size;
        int       nl = 0, ni = 0, *far = p1, n_far = np1;
        if (e == 0 && s->first_constraints > 0) {
            nl = s->first_constraints;
            for (int k = 0; k < nl; ++k) lambda[k] = first + s->interior_size - nl + k;
            for (int k = 0; k < s->interior_size - nl; ++k) inner[ni++] = first + k;
        } else if (e == s->n_elements - 1 && s->last_constraints > 0) {
            nl = s->last_constraints;
            for (int k = 0; k < nl; ++k) lambda[k] = first + k;
            for (int k = nl; k < s->interior_size; ++k) inner[ni++] = first + k;
            far   = p0;
            n_far = np0;
        } else {
            for (int k = 0; k < s->interior_size; ++k) inner[ni++] = first + k;
        }
        set_block(m, inner, ni, inner, ni);
        set_block(m, inner, ni, p0, np0);
        set_block(m, p0, np0, inner, ni);
        set_block(m, inner, ni, p1, np1);
        set_block(m, p1, np1, inner, ni);
        set_block(m, p0, np0, p1, np1);
        set_block(m, p1, np1, p0, np0);
        if (nl > 0) {
            for (int j = 0; j < ni; ++j) shared[j] = lcg_uniform();
            for (int k = 0; k < nl; ++k)
                for (int j = 0; j < ni; ++j) {
                    m->a[lambda[k] + (size_t)inner[j] * n] =
                        shared[j] + s->constraint_gap * lcg_uniform();
                    m->stored[lambda[k] + (size_t)inner[j] * n] = 1;
                }
            set_block(m, lambda, nl, far, n_far);
            set_block(m, inner, ni, lambda, nl);
            set_block(m, far, n_far, lambda, nl);
        }
    }
    for (int i = 0; i < n; ++i)
        if (m->stored[i + (size_t)i * n]) m->a[i + (size_t)i * n] += s->mass;
    free(p0);
    free(p1);
    free(inner);
    free(lambda);
    free(shared);
}

/* A regular rod of `elements` elements with nodes of 12 unknowns (one a multiplier) and
   interiors of 10. */
static rod_shape_t plain_rod(int elements)
{
    rod_shape_t s;
    memset(&s, 0, sizeof(s));
    s.n_elements    = elements;
    s.node_size     = 12;
    s.interior_size = 10;
    s.mass          = sqrt(2.0 * s.node_size + s.interior_size);
    return s;
}

/* The pattern and values of m as MATSEQAIJ (explicit zeros kept: they are in the pattern). */
static PetscErrorCode mat_fill(const rod_matrix_t *m, Mat A)
{
    PetscInt    *cols;
    PetscScalar *values;

    PetscFunctionBeginUser;
    PetscCall(PetscMalloc2(m->n, &cols, m->n, &values));
    for (PetscInt i = 0; i < m->n; ++i) {
        PetscInt count = 0;
        for (PetscInt j = 0; j < m->n; ++j)
            if (m->stored[i + (size_t)j * m->n]) {
                cols[count]     = j;
                values[count++] = m->a[i + (size_t)j * m->n];
            }
        PetscCall(MatSetValues(A, 1, &i, count, cols, values, INSERT_VALUES));
    }
    PetscCall(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
    PetscCall(PetscFree2(cols, values));
    PetscFunctionReturn(0);
}

static PetscErrorCode mat_create(const rod_matrix_t *m, Mat *A)
{
    PetscInt *nnz;

    PetscFunctionBeginUser;
    PetscCall(PetscCalloc1(m->n, &nnz));
    for (PetscInt j = 0; j < m->n; ++j)
        for (PetscInt i = 0; i < m->n; ++i) nnz[i] += m->stored[i + (size_t)j * m->n];
    PetscCall(MatCreateSeqAIJ(PETSC_COMM_SELF, m->n, m->n, 0, nnz, A));
    PetscCall(MatSetOption(*A, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
    PetscCall(mat_fill(m, *A));
    PetscCall(PetscFree(nnz));
    PetscFunctionReturn(0);
}

/* The CSR pattern and values of m, for rs_chain_lu directly. */
typedef struct {
    int     n;
    int    *row_ptr, *cols;
    double *values;
} csr_t;

static void csr_from(const rod_matrix_t *m, csr_t *c)
{
    const int n = m->n;
    int       nnz = 0;

    for (size_t k = 0; k < (size_t)n * n; ++k) nnz += m->stored[k];
    c->n          = n;
    c->row_ptr    = malloc(((size_t)n + 1) * sizeof(int));
    c->cols       = malloc((size_t)nnz * sizeof(int));
    c->values     = malloc((size_t)nnz * sizeof(double));
    c->row_ptr[0] = 0;
    for (int i = 0, e = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j)
            if (m->stored[i + (size_t)j * n]) {
                c->cols[e]     = j;
                c->values[e++] = m->a[i + (size_t)j * n];
            }
        c->row_ptr[i + 1] = e;
    }
}

static void csr_free(csr_t *c)
{
    free(c->row_ptr);
    free(c->cols);
    free(c->values);
}

/* ---- Measures ---------------------------------------------------------------------------- */





/* ---- Bounds ------------------------------------------------------------------------------ */

/* Normwise backward error of a solve: rodchain's with panels about as well conditioned as the
   matrix, and MUMPS's, achieve 0.3 to 3 eps here; 16 eps is 5 to 50 times that, while a wrong
   factor or a wrong package gives O(1). */
static const double backward_bound = 16.0 * DBL_EPSILON;

/* The same for a chain of 36 to 60 elements (800 to 1350 unknowns): the chain LU pivots within
   its panels only, and its backward error grows along the chain (measured 0.6e-15 to 1.4e-14
   over seeds and lengths, in the matrix's order and in the breadth-first chain order alike;
   dgesv 2e-16); 1e-13 is 7 to 170 times that, while a wrong factor or order gives O(1). */
static const double long_chain_backward_bound = 1e-13;

/* The difference of two solutions relative to the second, over kappa (eta_1 + eta_2): to first
   order each is within kappa eta (1 + ||b|| / (||A|| ||x||)) <= 2 kappa eta of the exact one,
   kappa being the infinity-norm condition number (dgecon's estimate); achieved 0.01 to 0.2. */
static const double forward_bound = 2.0;

/* A right-hand side b = A x for a random x, as a Vec and as an array. */
static PetscErrorCode random_right_hand_side(const rod_matrix_t *m, Vec b, double *bb)
{
    PetscScalar *v;

    PetscFunctionBeginUser;
    for (int i = 0; i < m->n; ++i) bb[i] = 0.0;
    for (int j = 0; j < m->n; ++j) {
        const double xj = lcg_uniform();
        for (int i = 0; i < m->n; ++i) bb[i] += m->a[i + (size_t)j * m->n] * xj;
    }
    PetscCall(VecGetArray(b, &v));
    for (int i = 0; i < m->n; ++i) v[i] = bb[i];
    PetscCall(VecRestoreArray(b, &v));
    PetscFunctionReturn(0);
}

/* Checks x against dgesv's solution of m x = b: backward error and difference. */
static PetscErrorCode check_solution(const rod_matrix_t *m, const double *b, Vec x,
                                     const char *label)
{
    const PetscScalar *v;
    double            *x_ref = malloc((size_t)m->n * sizeof(double)), condition, eta, eta_ref;
    double             difference = 0.0;
    char               what[128];

    PetscFunctionBeginUser;
    dense_solve(m, b, x_ref, &condition);
    eta_ref = backward_error(m, x_ref, b);
    PetscCall(VecGetArrayRead(x, &v));
    eta = backward_error(m, v, b);
    for (int i = 0; i < m->n; ++i)
        if (!(fabs(v[i] - x_ref[i]) <= difference)) difference = fabs(v[i] - x_ref[i]);
    PetscCall(VecRestoreArrayRead(x, &v));
    printf("    %s: n = %d, condition estimate %.3g, dgesv's backward error %.3g\n", label,
           m->n, condition, eta_ref);
    snprintf(what, sizeof(what), "%s: backward error", label);
    CHECK_BELOW(eta, backward_bound, what);
    snprintf(what, sizeof(what), "%s: |x - x_dgesv| / (kappa (eta + eta_dgesv) |x|)", label);
    CHECK_BELOW(difference / norm_inf_vector(m->n, x_ref) / (condition * (eta + eta_ref)),
                forward_bound, what);
    free(x_ref);
    PetscFunctionReturn(0);
}

/* ---- KSPs -------------------------------------------------------------------------------- */

/* preonly + PCLU with the package `type` set in code, then the options (prefix `prefix`). */
static PetscErrorCode lu_ksp(Mat A, const char *type, const char *prefix, KSP *ksp)
{
    PC pc;

    PetscFunctionBeginUser;
    PetscCall(KSPCreate(PETSC_COMM_SELF, ksp));
    PetscCall(KSPSetOptionsPrefix(*ksp, prefix));
    PetscCall(KSPSetOperators(*ksp, A, A));
    PetscCall(KSPSetType(*ksp, KSPPREONLY));
    PetscCall(KSPGetPC(*ksp, &pc));
    PetscCall(PCSetType(pc, PCLU));
    PetscCall(PCFactorSetMatSolverType(pc, type));
    PetscCall(KSPSetFromOptions(*ksp));
    PetscFunctionReturn(0);
}

/* The package of the KSP's factor matrix (after setup). */
static PetscErrorCode factor_of(KSP ksp, Mat *F, MatSolverType *type)
{
    PC pc;

    PetscFunctionBeginUser;
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PCFactorGetMatrix(pc, F));
    PetscCall(MatFactorGetSolverType(*F, type));
    PetscFunctionReturn(0);
}

/* Factorizations of the KSP's rodchain factor: by the chain, by MUMPS. */
static PetscErrorCode stats_of(KSP ksp, PetscInt *chain, PetscInt *fallback)
{
    Mat           F;
    MatSolverType type;

    PetscFunctionBeginUser;
    PetscCall(factor_of(ksp, &F, &type));
    PetscCall(rs_rodchain_get_stats(F, chain, fallback));
    PetscFunctionReturn(0);
}

/* Solve m x = b for a random b; the normwise backward error of x. */
static PetscErrorCode solve_backward_error(KSP ksp, const rod_matrix_t *m, double *eta)
{
    Vec                b, x;
    const PetscScalar *v;
    double            *bb = malloc((size_t)m->n * sizeof(double));

    PetscFunctionBeginUser;
    PetscCall(VecCreateSeq(PETSC_COMM_SELF, m->n, &b));
    PetscCall(VecDuplicate(b, &x));
    PetscCall(random_right_hand_side(m, b, bb));
    PetscCall(KSPSolve(ksp, b, x));
    PetscCall(VecGetArrayRead(x, &v));
    *eta = backward_error(m, v, bb);
    PetscCall(VecRestoreArrayRead(x, &v));
    PetscCall(VecDestroy(&b));
    PetscCall(VecDestroy(&x));
    free(bb);
    PetscFunctionReturn(0);
}

/* Solve and check the result against dgesv; the KSP must converge. */
static PetscErrorCode solve_and_check(KSP ksp, const rod_matrix_t *m, const char *label)
{
    Vec                b, x;
    double            *bb = malloc((size_t)m->n * sizeof(double));
    KSPConvergedReason reason;

    PetscFunctionBeginUser;
    PetscCall(VecCreateSeq(PETSC_COMM_SELF, m->n, &b));
    PetscCall(VecDuplicate(b, &x));
    PetscCall(random_right_hand_side(m, b, bb));
    PetscCall(KSPSolve(ksp, b, x));
    PetscCall(KSPGetConvergedReason(ksp, &reason));
    CHECK(reason > 0, "%s: the KSP converged, reason %s", label, KSPConvergedReasons[reason]);
    PetscCall(check_solution(m, bb, x, label));
    PetscCall(VecDestroy(&b));
    PetscCall(VecDestroy(&x));
    free(bb);
    PetscFunctionReturn(0);
}

/* rs_chain_lu's verdict on m from both ends of the chain: numeric's return value each. */
static void chain_verdict(const rod_matrix_t *m, int *forward, int *backward)
{
    csr_t        c;
    rs_chain_lu *lu = NULL;
    int         *perm = malloc((size_t)m->n * sizeof(int));

    csr_from(m, &c);
    for (int p = 0; p < m->n; ++p) perm[p] = m->n - 1 - p;
    *forward = *backward = -1;
    if (rs_chain_lu_symbolic(c.n, c.row_ptr, c.cols, &lu) == 0)
        *forward = rs_chain_lu_numeric(lu, c.values, 1e-13);
    rs_chain_lu_free(lu);
    lu = NULL;
    if (rs_chain_lu_symbolic_permuted(c.n, c.row_ptr, c.cols, perm, &lu) == 0)
        *backward = rs_chain_lu_numeric(lu, c.values, 1e-13);
    rs_chain_lu_free(lu);
    free(perm);
    csr_free(&c);
}

/* ---- Tests ------------------------------------------------------------------------------- */

/* rodchain and MUMPS solve the same system alike, and both as dgesv does. */
static PetscErrorCode test_matches_mumps(void)
{
    rod_shape_t        s = plain_rod(10);
    rod_matrix_t       m;
    Mat                A, F;
    KSP                ksp[2];
    Vec                b, x[2];
    double            *bb, condition, *x_ref, eta[2], difference = 0.0;
    const char        *types[2] = {MATSOLVERRODCHAIN, MATSOLVERMUMPS};
    MatSolverType      type;
    PetscInt           chain, fallback;
    KSPConvergedReason reason;

    PetscFunctionBeginUser;
    rod_matrix_make(&s, 1, &m);
    bb    = malloc((size_t)m.n * sizeof(double));
    x_ref = malloc((size_t)m.n * sizeof(double));
    PetscCall(mat_create(&m, &A));
    PetscCall(VecCreateSeq(PETSC_COMM_SELF, m.n, &b));
    PetscCall(random_right_hand_side(&m, b, bb));
    dense_solve(&m, bb, x_ref, &condition);
    for (int k = 0; k < 2; ++k) {
        const PetscScalar *v;
        PetscCall(VecDuplicate(b, &x[k]));
        PetscCall(lu_ksp(A, types[k], k == 0 ? "a_" : "b_", &ksp[k]));
        PetscCall(KSPSolve(ksp[k], b, x[k]));
        PetscCall(KSPGetConvergedReason(ksp[k], &reason));
        CHECK(reason > 0, "%s: converged, reason %s", types[k], KSPConvergedReasons[reason]);
        PetscCall(factor_of(ksp[k], &F, &type));
        printf("    factor package %s (asked for %s)\n", type, types[k]);
        CHECK(!strcmp(type, types[k]), "the factor is %s's, got %s", types[k], type);
        PetscCall(VecGetArrayRead(x[k], &v));
        eta[k] = backward_error(&m, v, bb);
        PetscCall(VecRestoreArrayRead(x[k], &v));
        CHECK_BELOW(eta[k], backward_bound,
                    k == 0 ? "rodchain: backward error" : "mumps: backward error");
    }
    PetscCall(stats_of(ksp[0], &chain, &fallback));
    printf("    n = %d, condition estimate %.3g; rodchain: %d by the chain, %d by MUMPS\n", m.n,
           condition, (int)chain, (int)fallback);
    CHECK(chain == 1 && fallback == 0, "one factorization, by the chain: %d, %d", (int)chain,
          (int)fallback);
    {
        const PetscScalar *v0, *v1;
        PetscCall(VecGetArrayRead(x[0], &v0));
        PetscCall(VecGetArrayRead(x[1], &v1));
        for (int i = 0; i < m.n; ++i)
            if (!(fabs(v0[i] - v1[i]) <= difference)) difference = fabs(v0[i] - v1[i]);
        CHECK_BELOW(difference / norm_inf_vector(m.n, v1) / (condition * (eta[0] + eta[1])),
                    forward_bound, "|x_rodchain - x_mumps| / (kappa (eta + eta_mumps) |x|)");
        PetscCall(VecRestoreArrayRead(x[0], &v0));
        PetscCall(VecRestoreArrayRead(x[1], &v1));
    }
    PetscCall(check_solution(&m, bb, x[0], "rodchain against dgesv"));
    for (int k = 0; k < 2; ++k) {
        PetscCall(KSPDestroy(&ksp[k]));
        PetscCall(VecDestroy(&x[k]));
    }
    PetscCall(VecDestroy(&b));
    PetscCall(MatDestroy(&A));
    free(bb);
    free(x_ref);
    rod_matrix_free(&m);
    PetscFunctionReturn(0);
}

/* A rod bordered by the multipliers of ties at its two ends, numbered after it (one rod's
   block of a bundle's block Jacobi): in the matrix's order the start node couples to the last
   rows and the panels would hold the whole rod (more than RODCHAIN_LARGEST_PANEL = 400
   unknowns), so rodchain factors it in its breadth-first chain order, by the chain, with the
   backward error of a long chain in its own order. */
static PetscErrorCode test_bordered_rod_in_chain_order(void)
{
    const int        ties = 6;
    rod_shape_t      s    = plain_rod(40);
    rod_matrix_t     rod, m;
    Mat              A;
    KSP              ksp;
    csr_t            c;
    rs_chain_lu     *lu = NULL;
    rs_chain_lu_info natural;
    PetscInt         chain, fallback;
    int              primal[16], np, border[6];

    PetscFunctionBeginUser;
    rod_matrix_make(&s, 11, &rod);
    m.n      = rod.n + 2 * ties;
    m.a      = calloc((size_t)m.n * m.n, sizeof(double));
    m.stored = calloc((size_t)m.n * m.n, 1);
    for (int j = 0; j < rod.n; ++j)
        for (int i = 0; i < rod.n; ++i) {
            m.a[i + (size_t)j * m.n]      = rod.a[i + (size_t)j * rod.n];
            m.stored[i + (size_t)j * m.n] = rod.stored[i + (size_t)j * rod.n];
        }
    for (int end = 0; end < 2; ++end) {
        np = node_primal(&s, end == 0 ? 0 : s.n_elements, primal);
        for (int k = 0; k < ties; ++k) border[k] = rod.n + end * ties + k;
        set_block(&m, border, ties, primal, np);
        set_block(&m, primal, np, border, ties);
    }
    csr_from(&m, &c);
    natural.largest_panel = c.n;
    if (rs_chain_lu_symbolic(c.n, c.row_ptr, c.cols, &lu) == 0) rs_chain_lu_get_info(lu, &natural);
    rs_chain_lu_free(lu);
    csr_free(&c);
    printf("    n = %d; in the matrix's order the largest panel holds %d unknowns\n", m.n,
           natural.largest_panel);
    CHECK(natural.largest_panel > 400, "the matrix's order is no chain (largest panel %d)",
          natural.largest_panel);
    PetscCall(mat_create(&m, &A));
    PetscCall(lu_ksp(A, MATSOLVERRODCHAIN, "bordered_", &ksp));
    fallback_lines = 0;
    {
        double eta;
        PetscCall(solve_backward_error(ksp, &m, &eta));
        CHECK_BELOW(eta, long_chain_backward_bound, "bordered rod, chain order: backward error");
    }
    PetscCall(stats_of(ksp, &chain, &fallback));
    printf("    rodchain: %d by the chain, %d by MUMPS\n", (int)chain, (int)fallback);
    CHECK(chain == 1 && fallback == 0 && fallback_lines == 0,
          "one factorization, by the chain: %d, %d (%d fallback messages)", (int)chain,
          (int)fallback, fallback_lines);
    PetscCall(KSPDestroy(&ksp));
    PetscCall(MatDestroy(&A));
    rod_matrix_free(&rod);
    rod_matrix_free(&m);
    PetscFunctionReturn(0);
}

/* -pc_factor_mat_solver_type overrides the package set in code, both ways: rodchain does not
   take the choice from the options database; and rs_rodchain_get_stats refuses another
   package's factor. */
static PetscErrorCode test_options_select_the_package(void)
{
    rod_shape_t    s = plain_rod(3);
    rod_matrix_t   m;
    Mat            A, F;
    KSP            ksp;
    MatSolverType  type;
    PetscErrorCode error;
    PetscInt       chain = -1;
    const char    *cases[2][3] = {{MATSOLVERRODCHAIN, MATSOLVERMUMPS, "o_"},
                                  {MATSOLVERMUMPS, MATSOLVERRODCHAIN, "p_"}};

    PetscFunctionBeginUser;
    rod_matrix_make(&s, 2, &m);
    PetscCall(mat_create(&m, &A));
    for (int k = 0; k < 2; ++k) {
        char option[64];
        PetscCall(PetscSNPrintf(option, sizeof(option), "-%spc_factor_mat_solver_type",
                                cases[k][2]));
        PetscCall(PetscOptionsSetValue(NULL, option, cases[k][1]));
        PetscCall(lu_ksp(A, cases[k][0], cases[k][2], &ksp));
        PetscCall(KSPSetUp(ksp));
        PetscCall(factor_of(ksp, &F, &type));
        printf("    set in code %s, %s %s: factor package %s\n", cases[k][0], option,
               cases[k][1], type);
        CHECK(!strcmp(type, cases[k][1]), "%s %s selects %s, got %s", option, cases[k][1],
              cases[k][1], type);
        PetscCall(solve_and_check(ksp, &m, cases[k][1]));
        if (!strcmp(type, MATSOLVERMUMPS)) {
            PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
            error = rs_rodchain_get_stats(F, &chain, NULL);
            PetscCall(PetscPopErrorHandler());
            printf("    rs_rodchain_get_stats on the MUMPS factor: error %d\n", (int)error);
            CHECK(error == PETSC_ERR_ARG_WRONG && chain == -1,
                  "rs_rodchain_get_stats refuses a MUMPS factor, error %d", (int)error);
        }
        PetscCall(KSPDestroy(&ksp));
        PetscCall(PetscOptionsClearValue(NULL, option));
    }
    PetscCall(MatDestroy(&A));
    rod_matrix_free(&m);
    PetscFunctionReturn(0);
}

/* The first element's two constraint rows agree on its interior: singular on its own panel
   from the start of the chain, regular from its end. The reversed chain serves, no MUMPS. */
static PetscErrorCode test_first_panel_singular_uses_reversed_chain(void)
{
    rod_shape_t  s = plain_rod(6);
    rod_matrix_t m;
    Mat          A;
    KSP          ksp;
    PetscInt     chain, fallback;
    int          forward, backward, lines;

    PetscFunctionBeginUser;
    s.first_constraints = 2;
    rod_matrix_make(&s, 3, &m);
    chain_verdict(&m, &forward, &backward);
    printf("    rs_chain_lu_numeric from the start %d, from the end %d\n", forward, backward);
    CHECK(forward == 1 && backward == 0,
          "premise: the first panel is singular from the start only (%d, %d)", forward,
          backward);
    PetscCall(mat_create(&m, &A));
    PetscCall(lu_ksp(A, MATSOLVERRODCHAIN, "c_", &ksp));
    lines = fallback_lines;
    PetscCall(solve_and_check(ksp, &m, "from the end"));
    PetscCall(stats_of(ksp, &chain, &fallback));
    printf("    %d by the chain, %d by MUMPS, %d lines about MUMPS\n", (int)chain, (int)fallback,
           fallback_lines - lines);
    CHECK(chain == 1 && fallback == 0, "by the chain (reversed), not MUMPS: %d, %d", (int)chain,
          (int)fallback);
    CHECK(fallback_lines == lines, "no line about MUMPS");
    PetscCall(KSPDestroy(&ksp));
    PetscCall(MatDestroy(&A));
    rod_matrix_free(&m);
    PetscFunctionReturn(0);
}

/* Both end elements constrained that way: singular from either end, regular as a whole.
   MUMPS serves, with one line on standard output for two factorizations. */
static PetscErrorCode test_singular_from_both_ends_uses_mumps(void)
{
    rod_shape_t  s = plain_rod(6);
    rod_matrix_t m[2];
    Mat          A;
    KSP          ksp;
    PetscInt     chain, fallback;
    int          forward, backward, lines;

    PetscFunctionBeginUser;
    s.first_constraints = 2;
    s.last_constraints  = 2;
    for (int k = 0; k < 2; ++k) rod_matrix_make(&s, 4 + (uint64_t)k, &m[k]);
    chain_verdict(&m[0], &forward, &backward);
    printf("    rs_chain_lu_numeric from the start %d, from the end %d\n", forward, backward);
    CHECK(forward == 1 && backward == 1,
          "premise: the first panel is singular from both ends (%d, %d)", forward, backward);
    PetscCall(mat_create(&m[0], &A));
    PetscCall(lu_ksp(A, MATSOLVERRODCHAIN, "d_", &ksp));
    lines = fallback_lines;
    PetscCall(solve_and_check(ksp, &m[0], "by MUMPS"));
    PetscCall(mat_fill(&m[1], A));
    PetscCall(solve_and_check(ksp, &m[1], "by MUMPS, second values"));
    PetscCall(stats_of(ksp, &chain, &fallback));
    printf("    %d by the chain, %d by MUMPS, %d lines about MUMPS\n", (int)chain, (int)fallback,
           fallback_lines - lines);
    CHECK(chain == 0 && fallback == 2, "both by MUMPS: %d, %d", (int)chain, (int)fallback);
    CHECK(fallback_lines - lines == 1, "one line about MUMPS, got %d", fallback_lines - lines);
    PetscCall(KSPDestroy(&ksp));
    PetscCall(MatDestroy(&A));
    for (int k = 0; k < 2; ++k) rod_matrix_free(&m[k]);
    PetscFunctionReturn(0);
}

/* The first element's constraint rows differ by 1e-9 on its interior: the chain passes its
   pivot test (a pivot of ~1e-9 of its column) but its backward error is ~1e-8, so the check of
   the first solve (-mat_rodchain_check_tol 1e-10) hands the factorization to MUMPS; with the
   check off, the chain's factorization stays. */
static PetscErrorCode test_nearly_singular_panel_caught_by_the_check(void)
{
    rod_shape_t  s = plain_rod(6);
    rod_matrix_t m;
    Mat          A;
    KSP          ksp;
    PetscInt     chain, fallback;
    int          forward, backward;

    PetscFunctionBeginUser;
    s.first_constraints = 2;
    s.constraint_gap    = 1e-9;
    rod_matrix_make(&s, 5, &m);
    chain_verdict(&m, &forward, &backward);
    {
        /* The premise: the chain's own backward error here, from the start of the chain. */
        csr_t        c;
        rs_chain_lu *lu = NULL;
        double      *b = malloc((size_t)m.n * sizeof(double));
        double      *x = malloc((size_t)m.n * sizeof(double));
        double       eta = HUGE_VAL;
        csr_from(&m, &c);
        for (int i = 0; i < m.n; ++i) b[i] = lcg_uniform();
        if (rs_chain_lu_symbolic(c.n, c.row_ptr, c.cols, &lu) == 0 &&
            rs_chain_lu_numeric(lu, c.values, 1e-13) == 0) {
            rs_chain_lu_solve(lu, b, x);
            eta = backward_error(&m, x, b);
        }
        printf("    rs_chain_lu_numeric from the start %d, from the end %d; backward error of "
               "a chain solve %.3g\n", forward, backward, eta);
        CHECK(forward == 0 && eta > 1e-10 && eta < 1.0,
              "premise: the chain factors it from the start, badly (%d, %.3g)", forward, eta);
        rs_chain_lu_free(lu);
        csr_free(&c);
        free(b);
        free(x);
    }
    PetscCall(mat_create(&m, &A));
    PetscCall(lu_ksp(A, MATSOLVERRODCHAIN, "e_", &ksp));
    PetscCall(solve_and_check(ksp, &m, "after the check"));
    PetscCall(solve_and_check(ksp, &m, "second right-hand side"));
    PetscCall(stats_of(ksp, &chain, &fallback));
    printf("    %d by the chain, %d by MUMPS\n", (int)chain, (int)fallback);
    CHECK(chain == 0 && fallback == 1, "the check gave it to MUMPS: %d, %d", (int)chain,
          (int)fallback);
    PetscCall(KSPDestroy(&ksp));

    /* The control: with the check off (the option of the matrix, read when the factor is
       made), the chain's factorization stays, with its backward error. */
    PetscCall(PetscOptionsSetValue(NULL, "-mat_rodchain_check_tol", "0"));
    PetscCall(lu_ksp(A, MATSOLVERRODCHAIN, "e2_", &ksp));
    {
        double eta;
        PetscCall(solve_backward_error(ksp, &m, &eta));
        PetscCall(stats_of(ksp, &chain, &fallback));
        printf("    -mat_rodchain_check_tol 0: %d by the chain, %d by MUMPS, backward error "
               "%.3g\n", (int)chain, (int)fallback, eta);
        CHECK(chain == 1 && fallback == 0 && eta > 1e-10,
              "without the check the chain's factor stays: %d, %d, backward error %.3g",
              (int)chain, (int)fallback, eta);
    }
    PetscCall(PetscOptionsClearValue(NULL, "-mat_rodchain_check_tol"));
    PetscCall(KSPDestroy(&ksp));
    PetscCall(MatDestroy(&A));
    rod_matrix_free(&m);
    PetscFunctionReturn(0);
}

/* A zero row: the chain refuses it from both ends, MUMPS too, so the PC fails
   (KSP_DIVERGED_PC_FAILED) and the solution holds no finite number. The next values (regular,
   same pattern) are factored by the chain again. */
static PetscErrorCode test_singular_matrix_fails_the_pc(void)
{
    rod_shape_t        s = plain_rod(4);
    rod_matrix_t       m;
    const int          row = node_start(&s, 2) + s.node_size + 3;
    Mat                A;
    KSP                ksp;
    PC                 pc;
    Vec                b, x;
    double            *bb;
    PetscInt           chain, fallback, finite = 0;
    KSPConvergedReason reason;
    PCFailedReason     failed;
    int                forward, backward;
    const PetscScalar *v;
    PetscScalar       *w;

    PetscFunctionBeginUser;
    rod_matrix_make(&s, 6, &m);
    for (int j = 0; j < m.n; ++j) m.a[row + (size_t)j * m.n] = 0.0;
    chain_verdict(&m, &forward, &backward);
    printf("    rs_chain_lu_numeric from the start %d, from the end %d\n", forward, backward);
    CHECK(forward > 0 && backward > 0, "premise: refused from both ends (%d, %d)", forward,
          backward);
    bb = malloc((size_t)m.n * sizeof(double));
    PetscCall(mat_create(&m, &A));
    PetscCall(VecCreateSeq(PETSC_COMM_SELF, m.n, &b));
    PetscCall(VecDuplicate(b, &x));
    for (int i = 0; i < m.n; ++i) bb[i] = lcg_uniform();
    PetscCall(VecGetArray(b, &w));
    for (int i = 0; i < m.n; ++i) w[i] = bb[i];
    PetscCall(VecRestoreArray(b, &w));
    PetscCall(lu_ksp(A, MATSOLVERRODCHAIN, "f_", &ksp));
    PetscCall(KSPSolve(ksp, b, x));
    PetscCall(KSPGetConvergedReason(ksp, &reason));
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PCGetFailedReason(pc, &failed));
    PetscCall(VecGetArrayRead(x, &v));
    for (int i = 0; i < m.n; ++i) finite += isfinite(v[i]) ? 1 : 0;
    PetscCall(VecRestoreArrayRead(x, &v));
    PetscCall(stats_of(ksp, &chain, &fallback));
    printf("    KSP %s, PC %s, %d finite entries of %d; %d by the chain, %d by MUMPS\n",
           KSPConvergedReasons[reason], PCFailedReasons[failed], (int)finite, m.n, (int)chain,
           (int)fallback);
    CHECK(reason == KSP_DIVERGED_PC_FAILED, "KSP_DIVERGED_PC_FAILED, got %s",
          KSPConvergedReasons[reason]);
    CHECK(failed == PC_FACTOR_NUMERIC_ZEROPIVOT, "the PC failed with a zero pivot, got %s",
          PCFailedReasons[failed]);
    CHECK(finite == 0, "no finite entry in the solution, got %d", (int)finite);
    CHECK(chain == 0 && fallback == 1, "refused by the chain, tried by MUMPS: %d, %d",
          (int)chain, (int)fallback);

    /* A regular Jacobian next (a cut step): the chain factors it. */
    rod_matrix_free(&m);
    rod_matrix_make(&s, 7, &m);
    PetscCall(mat_fill(&m, A));
    PetscCall(solve_and_check(ksp, &m, "regular values after the failure"));
    PetscCall(stats_of(ksp, &chain, &fallback));
    printf("    %d by the chain, %d by MUMPS\n", (int)chain, (int)fallback);
    CHECK(chain == 1 && fallback == 1, "the chain again: %d, %d", (int)chain, (int)fallback);
    PetscCall(KSPDestroy(&ksp));
    PetscCall(VecDestroy(&b));
    PetscCall(VecDestroy(&x));
    PetscCall(MatDestroy(&A));
    free(bb);
    rod_matrix_free(&m);
    PetscFunctionReturn(0);
}

/* After the chain failed, it is tried at the 1st, 2nd, 4th, 8th, ... factorization since
   (rodchain.c, TryChain; the line it prints says so): three Jacobians singular from both ends,
   then regular ones of the same pattern. The chain fails at the first and is retried (and
   fails) after the 1st and the 2nd MUMPS factorization since; after the 3rd it is not tried,
   MUMPS factors the regular Jacobian; after the 4th the chain serves again. */
/* The matrices of chain_retried_after_1_2_4_fallbacks, singular on their first panel from
   either end with the first plan, are factored by the chain after a re-plan of its panels
   (rs_chain_lu_replan, the default -mat_rodchain_replans 2): right solution, no MUMPS. */
static PetscErrorCode test_replan_rescues_constrained_rod(void)
{
    rod_shape_t  bad = plain_rod(4);
    rod_matrix_t m;
    Mat          A;
    KSP          ksp;
    PetscInt     chain, fallback;

    PetscFunctionBeginUser;
    bad.first_constraints = bad.last_constraints = 2;
    rod_matrix_make(&bad, 10, &m);
    PetscCall(mat_create(&m, &A));
    PetscCall(lu_ksp(A, MATSOLVERRODCHAIN, "r_", &ksp));
    PetscCall(solve_and_check(ksp, &m, "after a re-plan"));
    PetscCall(stats_of(ksp, &chain, &fallback));
    printf("    %d by the chain, %d by MUMPS\n", (int)chain, (int)fallback);
    CHECK(chain == 1 && fallback == 0, "the re-planned chain serves: %d, %d", (int)chain,
          (int)fallback);
    PetscCall(KSPDestroy(&ksp));
    PetscCall(MatDestroy(&A));
    rod_matrix_free(&m);
    PetscFunctionReturn(0);
}

static PetscErrorCode test_chain_retried_after_1_2_4_fallbacks(void)
{
    rod_shape_t  bad = plain_rod(4), good = plain_rod(4);
    rod_matrix_t m;
    Mat          A;
    KSP          ksp;
    PetscInt     chain, fallback;
    /* After each of the five factorizations: expected counts (chain, MUMPS). */
    const int expected[5][2] = {{0, 1}, {0, 2}, {0, 3}, {0, 4}, {1, 4}};

    PetscFunctionBeginUser;
    /* The same pattern; the regular ones' constraint rows independent on their interior. */
    bad.first_constraints = bad.last_constraints = 2;
    good.first_constraints = good.last_constraints = 2;
    good.constraint_gap                           = 1.0;
    for (int k = 0; k < 5; ++k) {
        char label[64];
        rod_matrix_make(k < 3 ? &bad : &good, 10 + (uint64_t)k, &m);
        if (k == 0) {
            /* The back-off alone: no re-plans (these matrices are regular with another plan
               of the panels, see replan_rescues_constrained_rod). */
            PetscCall(PetscOptionsSetValue(NULL, "-mat_rodchain_replans", "0"));
            PetscCall(mat_create(&m, &A));
            PetscCall(lu_ksp(A, MATSOLVERRODCHAIN, "g_", &ksp));
            PetscCall(PetscOptionsClearValue(NULL, "-mat_rodchain_replans"));
        } else {
            PetscCall(mat_fill(&m, A));
        }
        PetscCall(PetscSNPrintf(label, sizeof(label), "factorization %d (%s)", k + 1,
                                k < 3 ? "singular from both ends" : "regular"));
        PetscCall(solve_and_check(ksp, &m, label));
        PetscCall(stats_of(ksp, &chain, &fallback));
        printf("    %d by the chain, %d by MUMPS (expected %d, %d)\n", (int)chain, (int)fallback,
               expected[k][0], expected[k][1]);
        CHECK(chain == expected[k][0] && fallback == expected[k][1],
              "after factorization %d: %d by the chain, %d by MUMPS, expected %d, %d", k + 1,
              (int)chain, (int)fallback, expected[k][0], expected[k][1]);
        rod_matrix_free(&m);
    }
    PetscCall(KSPDestroy(&ksp));
    PetscCall(MatDestroy(&A));
    PetscFunctionReturn(0);
}

/* One factorization, three right-hand sides; new values of the same pattern, two more. */
static PetscErrorCode test_reuse(void)
{
    rod_shape_t  s = plain_rod(8);
    rod_matrix_t m;
    Mat          A;
    KSP          ksp;
    PetscInt     chain, fallback;

    PetscFunctionBeginUser;
    for (int k = 0; k < 2; ++k) {
        rod_matrix_make(&s, 20 + (uint64_t)k, &m);
        if (k == 0) {
            PetscCall(mat_create(&m, &A));
            PetscCall(lu_ksp(A, MATSOLVERRODCHAIN, "h_", &ksp));
        } else {
            PetscCall(mat_fill(&m, A));
        }
        for (int rhs = 0; rhs < 3 - k; ++rhs) {
            char label[64];
            PetscCall(PetscSNPrintf(label, sizeof(label), "values %d, right-hand side %d",
                                    k + 1, rhs + 1));
            PetscCall(solve_and_check(ksp, &m, label));
        }
        PetscCall(stats_of(ksp, &chain, &fallback));
        printf("    %d by the chain, %d by MUMPS\n", (int)chain, (int)fallback);
        CHECK(chain == k + 1 && fallback == 0, "%d factorizations by the chain, got %d, %d",
              k + 1, (int)chain, (int)fallback);
        rod_matrix_free(&m);
    }
    PetscCall(KSPDestroy(&ksp));
    PetscCall(MatDestroy(&A));
    PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
    PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
    PetscCall(rs_rodchain_register());
    petsc_vfprintf = PetscVFPrintf;
    PetscVFPrintf  = counting_vfprintf;
    run_test("matches_mumps", test_matches_mumps);
    run_test("options_select_the_package", test_options_select_the_package);
    run_test("bordered_rod_in_chain_order", test_bordered_rod_in_chain_order);
    run_test("first_panel_singular_uses_reversed_chain",
             test_first_panel_singular_uses_reversed_chain);
    run_test("singular_from_both_ends_uses_mumps", test_singular_from_both_ends_uses_mumps);
    run_test("nearly_singular_panel_caught_by_the_check",
             test_nearly_singular_panel_caught_by_the_check);
    run_test("singular_matrix_fails_the_pc", test_singular_matrix_fails_the_pc);
    run_test("replan_rescues_constrained_rod", test_replan_rescues_constrained_rod);
    run_test("chain_retried_after_1_2_4_fallbacks", test_chain_retried_after_1_2_4_fallbacks);
    run_test("reuse", test_reuse);
    PetscVFPrintf = petsc_vfprintf;
    PetscCall(PetscFinalize());
    printf("%d passed, %d failed\n", n_passed, n_failed);
    return n_failed > 0 ? 1 : 0;
}
