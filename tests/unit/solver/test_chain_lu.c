/* Unit tests of the chain LU (include/rs_chain_lu.h, src/solver/chain_lu.c) against LAPACK's
   dense LU with partial pivoting (dgesv), on random matrices with the pattern of a rod's
   Jacobian: nodes and element interiors numbered along the rod, each element coupling its
   interior to its two end nodes and the two nodes to each other with dense random blocks.

   Checked: the solution in the matrix's order and from the other end of the chain agrees with
   dgesv's to a bound from the condition number, with a small normwise backward error, for
   1, 2, 5 and 40 elements and several seeds; saddle-point rows (node multipliers with a
   structural or an explicit zero diagonal) need the pivoting inside panels; couplings present
   in one direction only; the symbolic phase finds the chain (many panels, none larger than
   one element with its nodes, the flops of one panel per element); a first element whose
   constraint rows are dependent on its own is refused from the start of the chain and
   factored from its end; singular and NaN matrices are refused, never "solved"; malformed
   patterns are rejected. The substitution of two-entry rows before the chain, on matrices
   with ph_director's kinematic rows: every velocity substituted and the panels smaller than
   without, the diagonal unknown taken when it adds no entry, none when either would, zero
   and too small pivots (|a_ip / a_ie| > 1e8) and NaN refused, and a solve in place.

   Bookkeeping as in tests/support/assert.F90: a test passes when none of its checks failed,
   failures go to standard error as file:line: test: message, and the last line is
   "N passed, M failed" (exit status 1 if any failed). Achieved values go to standard output. */
#include "rs_chain_lu.h"
#include "dense_reference.h"

#include <fenv.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* LAPACK (the reference the chain LU is measured against). */

/* ---- Bookkeeping (tests/support/assert.F90) ---------------------------------------------- */

static int         n_passed, n_failed, failures_in_current;
static const char *current_test = "";

static void run_test(const char *name, void (*test)(void))
{
    current_test        = name;
    failures_in_current = 0;
    test();
    if (failures_in_current == 0) {
        ++n_passed;
        printf("[  PASSED  ] %s\n", name);
    } else {
        ++n_failed;
        printf("[  FAILED  ] %s (%d failed assertions)\n", name, failures_in_current);
    }
    fflush(stdout);
}

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

/* ---- Random numbers: a fixed-seed LCG (Knuth's MMIX constants), so every run is the same -- */





/* ---- Rod-like matrices ------------------------------------------------------------------- */

enum { BOTH_WAYS, NO_UPPER, NO_LOWER, LOWER_EVEN_ROWS, LOWER_FIRST_ROWS };

/* The shape of a rod's Jacobian. Unknowns along the rod: node 0, interior 0, node 1, ...,
   interior E-1, node E. Node multipliers are rows and columns coupled only to the other
   unknowns of their node, with a zero diagonal (explicit for the first, structural for the
   others), like the constraint rows of a joint. Constraint rows of element 0 (at the end of
   its interior) couple to its interior and to node 1 only, and their interior parts are equal
   up to `constraint_gap`, so that they are dependent unless node 1 is in the same panel: the
   first panel is singular (gap 0) or nearly so from the start of the chain and regular from
   its end. Element E-1 can have the mirror image (rows at the start of its interior, coupled
   to node E-1). `coupling` drops the blocks from a node or interior to the next node
   (NO_UPPER) or those back (NO_LOWER), so that the coupling of panels is one-sided, or keeps
   the blocks back only on the node's rows of even local index (LOWER_EVEN_ROWS) or on its
   first half (LOWER_FIRST_ROWS), so that fewer rows than columns of a panel couple to the
   one before (the chain LU then forms the coupling from the rows' side). `mass`
   plays the part of M / h^2 in a dynamic rod's Jacobian: with none, the random blocks make
   panels that are much worse conditioned than the whole matrix. */
typedef struct {
    int    n_elements, node_size, interior_size;
    int    node_multipliers, multiplier_offset;
    int    first_constraints, last_constraints;
    double constraint_gap;
    int    coupling;
    double mass; /* added to the diagonal of every unknown but multipliers and constraints */
} rod_shape_t;


/* A CSR copy of a rod_matrix_t (0-based, sorted columns). */
typedef struct {
    int     n, nnz;
    int    *row_ptr, *cols;
    double *values;
} csr_t;

static int node_start(const rod_shape_t *s, int e)
{
    return e * (s->node_size + s->interior_size);
}

static int rod_size(const rod_shape_t *s)
{
    return node_start(s, s->n_elements) + s->node_size;
}

/* Segment of an unknown: 2e for node e, 2e + 1 for interior e. */
static int segment_of(const rod_shape_t *s, int i)
{
    const int stride = s->node_size + s->interior_size;
    return 2 * (i / stride) + (i % stride >= s->node_size);
}

static int is_node_multiplier(const rod_shape_t *s, int i)
{
    const int local = i % (s->node_size + s->interior_size);
    return local >= s->multiplier_offset && local < s->multiplier_offset + s->node_multipliers;
}

static void set_entry(const rod_shape_t *s, rod_matrix_t *m, int i, int j, double value)
{
    const int si = segment_of(s, i), sj = segment_of(s, j);
    /* The blocks between a node or an interior and the next node (even segment, later). */
    if (s->coupling == NO_UPPER && sj % 2 == 0 && sj > si) return;
    if (s->coupling == NO_LOWER && si % 2 == 0 && si > sj) return;
    if (s->coupling == LOWER_EVEN_ROWS && si % 2 == 0 && si > sj &&
        (i - node_start(s, si / 2)) % 2)
        return;
    if (s->coupling == LOWER_FIRST_ROWS && si % 2 == 0 && si > sj &&
        i - node_start(s, si / 2) >= s->node_size / 2)
        return;
    m->a[i + (size_t)j * m->n]      = value;
    m->stored[i + (size_t)j * m->n] = 1;
}

/* Dense random blocks rows x columns (index lists). */
static void set_block(const rod_shape_t *s, rod_matrix_t *m, const int *rows, int n_rows,
                      const int *cols, int n_cols)
{
    for (int j = 0; j < n_cols; ++j)
        for (int i = 0; i < n_rows; ++i) set_entry(s, m, rows[i], cols[j], lcg_uniform());
}

/* The node's unknowns other than its multipliers. */
static int node_primal(const rod_shape_t *s, int e, int *list)
{
    int count = 0;
    for (int i = node_start(s, e); i < node_start(s, e) + s->node_size; ++i)
        if (!is_node_multiplier(s, i)) list[count++] = i;
    return count;
}


static void rod_matrix_make(const rod_shape_t *s, uint64_t seed, rod_matrix_t *m)
{
    const int n = rod_size(s);
    int      *p0 = malloc((size_t)n * sizeof(int)), *p1 = malloc((size_t)n * sizeof(int));
    int      *mult = malloc((size_t)n * sizeof(int)), *inner = malloc((size_t)n * sizeof(int));
    int      *lambda = malloc((size_t)n * sizeof(int));
    double   *shared = malloc((size_t)n * sizeof(double));

    lcg_seed(seed);
    m->n      = n;
    m->a      = calloc((size_t)n * n, sizeof(double));
    m->stored = calloc((size_t)n * n, 1);
    for (int e = 0; e <= s->n_elements; ++e) {
        const int np = node_primal(s, e, p0), nm = s->node_multipliers;
        for (int k = 0; k < nm; ++k) mult[k] = node_start(s, e) + s->multiplier_offset + k;
        set_block(s, m, p0, np, p0, np);
        set_block(s, m, mult, nm, p0, np);
        set_block(s, m, p0, np, mult, nm);
        if (nm > 0) set_entry(s, m, mult[0], mult[0], 0.0);
    }
    for (int e = 0; e < s->n_elements; ++e) {
        const int np0 = node_primal(s, e, p0), np1 = node_primal(s, e + 1, p1);
        const int first = node_start(s, e) + s->node_size;
        int       nl = 0, ni = 0, *far = p1, n_far = np1;
        /* Constraint rows of element 0 sit at the end of its interior and reach node 1; those
           of element E-1 at its start and reach node E-1 (the mirror image). */
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
        set_block(s, m, inner, ni, inner, ni);
        set_block(s, m, inner, ni, p0, np0);
        set_block(s, m, p0, np0, inner, ni);
        set_block(s, m, inner, ni, p1, np1);
        set_block(s, m, p1, np1, inner, ni);
        set_block(s, m, p0, np0, p1, np1);
        set_block(s, m, p1, np1, p0, np0);
        if (nl > 0) {
            for (int j = 0; j < ni; ++j) shared[j] = lcg_uniform();
            for (int k = 0; k < nl; ++k)
                for (int j = 0; j < ni; ++j)
                    set_entry(s, m, lambda[k], inner[j],
                              shared[j] + s->constraint_gap * lcg_uniform());
            set_block(s, m, lambda, nl, far, n_far);
            set_block(s, m, inner, ni, lambda, nl);
            set_block(s, m, far, n_far, lambda, nl);
        }
    }
    for (int i = 0; i < n; ++i)
        if (m->stored[i + (size_t)i * n] && m->a[i + (size_t)i * n] != 0.0)
            m->a[i + (size_t)i * n] += s->mass;
    free(p0);
    free(p1);
    free(mult);
    free(inner);
    free(lambda);
    free(shared);
}

static void csr_free(csr_t *c)
{
    free(c->row_ptr);
    free(c->cols);
    free(c->values);
    c->row_ptr = c->cols = NULL;
    c->values            = NULL;
}

static void csr_from(const rod_matrix_t *m, csr_t *c)
{
    const int n = m->n;
    int       nnz = 0;

    for (size_t k = 0; k < (size_t)n * n; ++k) nnz += m->stored[k];
    c->n       = n;
    c->nnz     = nnz;
    c->row_ptr = malloc(((size_t)n + 1) * sizeof(int));
    c->cols    = malloc((size_t)nnz * sizeof(int));
    c->values  = malloc((size_t)nnz * sizeof(double));
    c->row_ptr[0] = 0;
    for (int i = 0, e = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            if (m->stored[i + (size_t)j * n]) {
                c->cols[e]     = j;
                c->values[e++] = m->a[i + (size_t)j * n];
            }
        }
        c->row_ptr[i + 1] = e;
    }
}

/* ---- Measures ---------------------------------------------------------------------------- */




/* ||x - y|| / ||y||. */
static double relative_difference(int n, const double *x, const double *y)
{
    double difference = 0.0;
    for (int i = 0; i < n; ++i)
        if (!(fabs(x[i] - y[i]) <= difference)) difference = fabs(x[i] - y[i]);
    return difference / norm_inf_vector(n, y);
}


/* b = A x for a random x. */
static void random_right_hand_side(const rod_matrix_t *m, double *b)
{
    const int n = m->n;
    for (int i = 0; i < n; ++i) b[i] = 0.0;
    for (int j = 0; j < n; ++j) {
        const double xj = lcg_uniform();
        for (int i = 0; i < n; ++i) b[i] += m->a[i + (size_t)j * n] * xj;
    }
}

static int *reversed_order(int n)
{
    int *perm = malloc((size_t)n * sizeof(int));
    for (int p = 0; p < n; ++p) perm[p] = n - 1 - p;
    return perm;
}

/* ---- Bounds ------------------------------------------------------------------------------ */

/* Normwise backward error of a chain LU solve where the panels are about as well conditioned
   as the matrix (mass on the diagonal): partial pivoting inside panels of at most ~100
   unknowns then keeps the growth small; achieved 0.3 to 3 eps (dgesv: 0.3 to 1.3 eps), so
   16 eps is 5 to 50 times what is achieved, while a wrong coupling or pivot gives O(1). */
static const double backward_bound = 16.0 * DBL_EPSILON;

/* With the raw random blocks (no mass), a panel's own condition reaches 1e5, as large as the
   matrix's: the Schur complements grow and the chain LU's backward error reaches ~1000 eps
   (0.7 to 900 eps achieved over these seeds, dgesv: 0.4 to 1.3 eps). This is the weakness the
   rodchain package guards against with its check of the first solve (-mat_rodchain_check_tol
   1e-10); 2e-12 is 10 times the worst case here. */
static const double raw_backward_bound = 2e-12;

/* The difference from dgesv's solution relative to it, over kappa (eta + eta_dgesv): to first
   order each solution is within kappa eta (1 + ||b|| / (||A|| ||x||)) <= 2 kappa eta of the
   exact one (eta its normwise backward error, kappa the infinity-norm condition number, of
   which dgecon's is an estimate). So 2 is the bound; achieved 0.003 to 0.2 (0.0005 to 0.1
   without mass, where the chain's eta overstates its error; exactly 0 where the chain is a
   single panel, i.e. dgetrf itself), 10 to 600 times below. */
static const double forward_bound = 2.0;

/* Solve a matrix by the chain LU (the matrix's order and the reversed order) and by dgesv and
   compare; info (if not NULL) receives what symbolic found in each order (zeros if it failed). */
static void check_matrix_against_dense(const rod_matrix_t *m, double bound,
                                       const char *label, rs_chain_lu_info info[2])
{
    csr_t        c;
    rs_chain_lu *lu[2] = {NULL, NULL};
    int         *perm;
    double      *b, *x, *x_ref, condition, eta_ref;
    char         what[128];

    csr_from(m, &c);
    perm  = reversed_order(m->n);
    b     = malloc((size_t)m->n * sizeof(double));
    x     = malloc((size_t)m->n * sizeof(double));
    x_ref = malloc((size_t)m->n * sizeof(double));
    random_right_hand_side(m, b);
    dense_solve(m, b, x_ref, &condition);
    eta_ref = backward_error(m, x_ref, b);
    printf("  %s: n = %d, nnz = %d, condition estimate %.3g, dgesv's backward error %.3g\n",
           label, m->n, c.nnz, condition, eta_ref);
    CHECK(condition < 1e10, "%s: the test matrix is regular (condition %.3g)", label, condition);
    CHECK(rs_chain_lu_symbolic(c.n, c.row_ptr, c.cols, &lu[0]) == 0, "%s: symbolic", label);
    CHECK(rs_chain_lu_symbolic_permuted(c.n, c.row_ptr, c.cols, perm, &lu[1]) == 0,
          "%s: symbolic reversed", label);
    for (int d = 0; d < 2; ++d) {
        const char *direction = d == 0 ? "forward" : "reversed";
        double      eta;
        int         status;
        if (info) memset(&info[d], 0, sizeof(info[d]));
        if (!lu[d]) continue;
        if (info) rs_chain_lu_get_info(lu[d], &info[d]);
        status = rs_chain_lu_numeric(lu[d], c.values, 1e-13);
        CHECK(status == 0, "%s %s: numeric returned %d", label, direction, status);
        if (status != 0) continue;
        rs_chain_lu_solve(lu[d], b, x);
        eta = backward_error(m, x, b);
        snprintf(what, sizeof(what), "%s, %s: backward error", label, direction);
        CHECK_BELOW(eta, bound, what);
        snprintf(what, sizeof(what), "%s, %s: |x - x_dgesv| / (kappa (eta + eta_dgesv) |x|)",
                 label, direction);
        CHECK_BELOW(relative_difference(m->n, x, x_ref) / (condition * (eta + eta_ref)),
                    forward_bound, what);
    }
    rs_chain_lu_free(lu[0]);
    rs_chain_lu_free(lu[1]);
    free(perm);
    free(b);
    free(x);
    free(x_ref);
    csr_free(&c);
}

/* The same for the rod matrix of shape s and seed. */
static void check_against_dense(const rod_shape_t *s, uint64_t seed, double bound,
                                const char *label)
{
    rod_matrix_t m;

    rod_matrix_make(s, seed, &m);
    check_matrix_against_dense(&m, bound, label, NULL);
    rod_matrix_free(&m);
}

/* Sizes of a rod with `elements` elements drawn from the seed: nodes of 6 to 30 unknowns and
   interiors of 4 to 42 (smaller for the long chain, to keep the dense reference fast); a
   mass of the order of the spectral radius of the random blocks of a row. */
static rod_shape_t random_shape(int elements, uint64_t seed, int multipliers)
{
    rod_shape_t s;
    memset(&s, 0, sizeof(s));
    lcg_seed(seed + 1000);
    s.n_elements    = elements;
    s.node_size     = elements > 10 ? lcg_int(6, 12) : lcg_int(6, 30);
    s.interior_size = elements > 10 ? lcg_int(4, 18) : lcg_int(4, 42);
    if (multipliers) {
        s.node_multipliers  = lcg_int(1, 3);
        s.multiplier_offset = lcg_int(0, s.node_size - s.node_multipliers);
    }
    s.coupling = BOTH_WAYS;
    s.mass     = sqrt(2.0 * s.node_size + s.interior_size);
    return s;
}

/* ---- Tests ------------------------------------------------------------------------------- */

static const int element_counts[] = {1, 2, 5, 40};

static void test_rods_match_dense_lu(void)
{
    char label[96];
    for (size_t k = 0; k < sizeof(element_counts) / sizeof(element_counts[0]); ++k)
        for (uint64_t seed = 1; seed <= 3; ++seed) {
            const rod_shape_t s = random_shape(element_counts[k], seed, 0);
            snprintf(label, sizeof(label), "E=%d seed=%d (node %d, interior %d)",
                     s.n_elements, (int)seed, s.node_size, s.interior_size);
            check_against_dense(&s, seed, backward_bound, label);
        }
}

/* Node multipliers have a zero diagonal (structural, or an explicit 0.0 for the first), so
   dgetrf must pivot inside the panel; placed at random inside their node, so that the
   coupled rows and columns of a panel are not one contiguous range. */
static void test_saddle_rows_match_dense_lu(void)
{
    char label[96];
    for (size_t k = 0; k < sizeof(element_counts) / sizeof(element_counts[0]); ++k)
        for (uint64_t seed = 11; seed <= 13; ++seed) {
            const rod_shape_t s = random_shape(element_counts[k], seed, 1);
            snprintf(label, sizeof(label), "E=%d seed=%d (%d multipliers at %d of %d)",
                     s.n_elements, (int)seed, s.node_multipliers, s.multiplier_offset,
                     s.node_size);
            check_against_dense(&s, seed, backward_bound, label);
        }
}

/* The raw random blocks, no mass: panels much worse conditioned than the matrix. */
static void test_raw_random_blocks_match_dense_lu(void)
{
    char label[96];
    for (size_t k = 0; k < sizeof(element_counts) / sizeof(element_counts[0]); ++k)
        for (uint64_t seed = 11; seed <= 13; ++seed) {
            rod_shape_t s = random_shape(element_counts[k], seed, 1);
            s.mass        = 0.0;
            snprintf(label, sizeof(label), "E=%d seed=%d no mass", s.n_elements, (int)seed);
            check_against_dense(&s, seed, raw_backward_bound, label);
        }
}

/* Couplings to the next panel one way only (the Schur complement of a panel is empty and the
   solve must still carry the other coupling), or back from fewer rows than the columns
   forward (in one range or scattered). */
static void test_one_sided_coupling_matches_dense_lu(void)
{
    char label[96];
    static const char *names[] = {"", "lower only", "upper only", "lower on even rows",
                                  "lower on the first rows"};
    for (int coupling = NO_UPPER; coupling <= LOWER_FIRST_ROWS; ++coupling) {
        rod_shape_t s = random_shape(5, 21, 1);
        s.coupling    = coupling;
        snprintf(label, sizeof(label), "E=5 %s", names[coupling]);
        check_against_dense(&s, 21, backward_bound, label);
    }
}

/* The panels of a long chain: one element each, the flops of that partition at most. */
static void test_panels_follow_the_chain(void)
{
    rod_shape_t  s = random_shape(40, 3, 1);
    rod_matrix_t m;
    csr_t        c;
    rs_chain_lu *lu = NULL;

    rod_matrix_make(&s, 3, &m);
    csr_from(&m, &c);
    CHECK(rs_chain_lu_symbolic(c.n, c.row_ptr, c.cols, &lu) == 0, "symbolic");
    if (lu) {
        rs_chain_lu_info info;
        const int        element = s.node_size + s.interior_size;
        const int        primal  = s.node_size - s.node_multipliers;
        /* One panel per element (node and interior) plus the last node: each couples to the
           next through that node's non-multiplier unknowns. The panels minimize the flops
           over cuts at nodes, so they cost at most this partition. */
        const double one_panel = 2.0 / 3.0 * element * element * element +
                                 2.0 * element * element * primal +
                                 2.0 * primal * element * primal;
        const double per_element =
            s.n_elements * one_panel + 2.0 / 3.0 * s.node_size * s.node_size * s.node_size;
        const double dense = 2.0 / 3.0 * (double)c.n * c.n * c.n;

        rs_chain_lu_get_info(lu, &info);
        printf("  n = %d (node %d, interior %d): %d panels, largest %d, coupling at most %d, "
               "%.4g flops (one panel per element: %.4g, dense: %.4g), %.0f doubles\n",
               c.n, s.node_size, s.interior_size, info.n_panels, info.largest_panel,
               info.widest_coupling, info.flops, per_element, dense, info.doubles);
        CHECK(info.n_panels >= s.n_elements, "%d panels for %d elements", info.n_panels,
              s.n_elements);
        CHECK(info.largest_panel <= element + s.node_size,
              "largest panel %d at most an element with both nodes (%d)", info.largest_panel,
              element + s.node_size);
        CHECK(info.widest_coupling <= primal, "coupling %d at most a node's primal unknowns %d",
              info.widest_coupling, primal);
        /* The plan minimises its flops plus a fixed cost per panel (chain_lu.c,
           panel_overhead: the LAPACK calls), so it may merge panels at a few per cent more
           flops than one panel per element (1.005 measured); a plan that ignored the chain
           would cost a multiple. */
        CHECK_BELOW(info.flops / per_element, 1.1, "flops / flops of one panel per element");
        /* About (n / E)^3 E of n^3, times ~3 for the couplings: 2e-3 for 40 elements. */
        CHECK_BELOW(info.flops / dense, 1e-2, "flops / dense LU flops");
        CHECK(info.doubles < 0.05 * (double)c.n * c.n, "%.0f doubles stored, dense %.0f",
              info.doubles, (double)c.n * c.n);
    }
    rs_chain_lu_free(lu);
    csr_free(&c);
    rod_matrix_free(&m);
}

/* A second numeric factorization with other values of the same pattern, and a solve in place
   (x = b, allowed by the header). */
static void test_refactor_and_solve_in_place(void)
{
    rod_shape_t  s = random_shape(5, 31, 1);
    rod_matrix_t m[2];
    csr_t        c[2];
    rs_chain_lu *lu = NULL;
    double      *b, *x, *x_ref, condition;
    char         what[96];

    for (int k = 0; k < 2; ++k) {
        rod_matrix_make(&s, 31 + (uint64_t)k, &m[k]);
        csr_from(&m[k], &c[k]);
    }
    b     = malloc((size_t)m[0].n * sizeof(double));
    x     = malloc((size_t)m[0].n * sizeof(double));
    x_ref = malloc((size_t)m[0].n * sizeof(double));
    CHECK(rs_chain_lu_symbolic(c[0].n, c[0].row_ptr, c[0].cols, &lu) == 0, "symbolic");
    for (int k = 0; lu && k < 2; ++k) {
        CHECK(rs_chain_lu_numeric(lu, c[k].values, 1e-13) == 0, "numeric %d", k + 1);
        for (int rhs = 0; rhs < 2; ++rhs) {
            random_right_hand_side(&m[k], b);
            dense_solve(&m[k], b, x_ref, &condition);
            memcpy(x, b, (size_t)m[k].n * sizeof(double));
            rs_chain_lu_solve(lu, x, x);
            snprintf(what, sizeof(what), "values %d, right-hand side %d: backward error", k + 1,
                     rhs + 1);
            CHECK_BELOW(backward_error(&m[k], x, b), backward_bound, what);
            snprintf(what, sizeof(what), "values %d, right-hand side %d: |x - x_dgesv| / "
                     "(kappa (eta + eta_dgesv) |x|)", k + 1, rhs + 1);
            CHECK_BELOW(relative_difference(m[k].n, x, x_ref) /
                            (condition * (backward_error(&m[k], x, b) +
                                          backward_error(&m[k], x_ref, b))),
                        forward_bound, what);
        }
    }
    rs_chain_lu_free(lu);
    free(b);
    free(x);
    free(x_ref);
    for (int k = 0; k < 2; ++k) {
        csr_free(&c[k]);
        rod_matrix_free(&m[k]);
    }
}

/* A regular matrix raises no floating-point exception in numeric and solve (they run inside
   PETSc with traps off, but an Inf or NaN on the way would be a defect). */
static void test_no_floating_point_exceptions(void)
{
    rod_shape_t  s = random_shape(5, 41, 1);
    rod_matrix_t m;
    csr_t        c;
    rs_chain_lu *lu = NULL;
    double      *b, *x;
    int          raised;

    rod_matrix_make(&s, 41, &m);
    csr_from(&m, &c);
    b = malloc((size_t)m.n * sizeof(double));
    x = malloc((size_t)m.n * sizeof(double));
    random_right_hand_side(&m, b);
    CHECK(rs_chain_lu_symbolic(c.n, c.row_ptr, c.cols, &lu) == 0, "symbolic");
    if (lu) {
        feclearexcept(FE_ALL_EXCEPT);
        CHECK(rs_chain_lu_numeric(lu, c.values, 1e-13) == 0, "numeric");
        rs_chain_lu_solve(lu, b, x);
        raised = fetestexcept(FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW);
        printf("    invalid %d, division by zero %d, overflow %d\n", !!(raised & FE_INVALID),
               !!(raised & FE_DIVBYZERO), !!(raised & FE_OVERFLOW));
        CHECK(raised == 0, "no invalid, division-by-zero or overflow exception");
    }
    rs_chain_lu_free(lu);
    free(b);
    free(x);
    csr_free(&c);
    rod_matrix_free(&m);
}

/* A first element whose two constraint rows agree on its interior and differ only on node 1:
   the panel of node 0 and interior 0 is singular, the matrix is not. From the start of the
   chain numeric refuses panel 1; from its end (node 1 eliminated with interior 0) it factors,
   and the solution is dgesv's. */
static void test_first_panel_singular_from_start_only(void)
{
    rod_shape_t  s = random_shape(5, 51, 1);
    rod_matrix_t m;
    csr_t        c;
    rs_chain_lu *forward = NULL, *backward = NULL;
    int         *perm;
    double      *b, *x, *x_ref, condition;
    int          status;

    s.first_constraints = 2;
    rod_matrix_make(&s, 51, &m);
    csr_from(&m, &c);
    perm  = reversed_order(m.n);
    b     = malloc((size_t)m.n * sizeof(double));
    x     = malloc((size_t)m.n * sizeof(double));
    x_ref = malloc((size_t)m.n * sizeof(double));
    random_right_hand_side(&m, b);
    dense_solve(&m, b, x_ref, &condition);
    printf("    n = %d, condition estimate %.3g\n", m.n, condition);
    CHECK(condition < 1e10, "the matrix is regular (condition %.3g)", condition);
    CHECK(rs_chain_lu_symbolic(c.n, c.row_ptr, c.cols, &forward) == 0, "symbolic");
    CHECK(rs_chain_lu_symbolic_permuted(c.n, c.row_ptr, c.cols, perm, &backward) == 0,
          "symbolic reversed");
    if (forward && backward) {
        status = rs_chain_lu_numeric(forward, c.values, 1e-13);
        printf("    numeric from the start: %d\n", status);
        CHECK(status == 1, "numeric from the start refuses panel 1, returned %d", status);
        status = rs_chain_lu_numeric(backward, c.values, 1e-13);
        printf("    numeric from the end: %d\n", status);
        CHECK(status == 0, "numeric from the end succeeds, returned %d", status);
        if (status == 0) {
            rs_chain_lu_solve(backward, b, x);
            CHECK_BELOW(backward_error(&m, x, b), backward_bound, "backward error");
            CHECK_BELOW(relative_difference(m.n, x, x_ref) /
                            (condition *
                             (backward_error(&m, x, b) + backward_error(&m, x_ref, b))),
                        forward_bound, "|x - x_dgesv| / (kappa (eta + eta_dgesv) |x|)");
        }
    }
    rs_chain_lu_free(forward);
    rs_chain_lu_free(backward);
    free(perm);
    free(b);
    free(x);
    free(x_ref);
    csr_free(&c);
    rod_matrix_free(&m);
}

/* Factor a singular variant of a rod matrix, from both ends; numeric must refuse it with a
   panel number in 1..n_panels. */
static void check_refused(const rod_shape_t *s, rod_matrix_t *m, const char *label)
{
    csr_t        c;
    rs_chain_lu *lu[2] = {NULL, NULL};
    int         *perm = reversed_order(m->n);

    csr_from(m, &c);
    CHECK(rs_chain_lu_symbolic(c.n, c.row_ptr, c.cols, &lu[0]) == 0, "%s: symbolic", label);
    CHECK(rs_chain_lu_symbolic_permuted(c.n, c.row_ptr, c.cols, perm, &lu[1]) == 0,
          "%s: symbolic reversed", label);
    for (int d = 0; d < 2; ++d) {
        rs_chain_lu_info info;
        int              status;
        if (!lu[d]) continue;
        rs_chain_lu_get_info(lu[d], &info);
        status = rs_chain_lu_numeric(lu[d], c.values, 1e-13);
        printf("    %s, %s: numeric returned %d of %d panels\n", label,
               d == 0 ? "forward" : "reversed", status, info.n_panels);
        CHECK(status >= 1 && status <= info.n_panels, "%s %s: refused with a panel number, got %d",
              label, d == 0 ? "forward" : "reversed", status);
    }
    (void)s;
    rs_chain_lu_free(lu[0]);
    rs_chain_lu_free(lu[1]);
    free(perm);
    csr_free(&c);
}

/* Singular matrices: a zero row (its pattern kept), a row three times another in the same
   interior (round-off leaves a pivot of about eps, which the pivot test must catch), the
   first element's constraint rows equal on its interior and on node 1 (dependent in the
   whole matrix), and a NaN. */
static void test_singular_matrices_are_refused(void)
{
    rod_shape_t  s = random_shape(5, 61, 1);
    rod_matrix_t m;
    const int    n = rod_size(&s), row = node_start(&s, 2) + s.node_size + 1;

    rod_matrix_make(&s, 61, &m);
    for (int j = 0; j < n; ++j) m.a[row + (size_t)j * n] = 0.0;
    check_refused(&s, &m, "zero row");
    rod_matrix_free(&m);

    rod_matrix_make(&s, 61, &m);
    for (int j = 0; j < n; ++j) m.a[row + 1 + (size_t)j * n] = 3.0 * m.a[row + (size_t)j * n];
    check_refused(&s, &m, "row 3 times another");
    rod_matrix_free(&m);

    s.first_constraints = 2;
    rod_matrix_make(&s, 61, &m);
    {
        const int first = node_start(&s, 0) + s.node_size + s.interior_size - 2;
        for (int j = 0; j < n; ++j) m.a[first + 1 + (size_t)j * n] = m.a[first + (size_t)j * n];
    }
    check_refused(&s, &m, "equal constraint rows");
    rod_matrix_free(&m);
    s.first_constraints = 0;

    rod_matrix_make(&s, 61, &m);
    m.a[row + (size_t)row * n] = NAN;
    check_refused(&s, &m, "a NaN on the diagonal");
    rod_matrix_free(&m);
}

/* Patterns symbolic must reject with status 1 and *lu NULL. */
static void test_bad_patterns_are_rejected(void)
{
    /* A 3 x 3 tridiagonal pattern and broken copies of it. */
    const int    row_ptr[] = {0, 2, 5, 7}, cols[] = {0, 1, 0, 1, 2, 1, 2};
    const int    shifted[] = {1, 2, 5, 7}, decreasing[] = {0, 2, 1, 7};
    const int    too_large[] = {0, 1, 0, 1, 3, 1, 2}, negative[] = {0, 1, -1, 1, 2, 1, 2};
    const int    duplicate_perm[] = {2, 1, 2}, outside_perm[] = {2, 1, 3};
    rs_chain_lu *lu;
    struct {
        const char *what;
        int         n;
        const int  *row_ptr, *cols, *perm;
    } cases[] = {
        {"row_ptr[0] = 1", 3, shifted, cols, NULL},
        {"row_ptr decreasing", 3, decreasing, cols, NULL},
        {"a column = n", 3, row_ptr, too_large, NULL},
        {"a column = -1", 3, row_ptr, negative, NULL},
        {"n = 0", 0, row_ptr, cols, NULL},
        {"perm with a repeated entry", 3, row_ptr, cols, duplicate_perm},
        {"perm with an entry = n", 3, row_ptr, cols, outside_perm},
    };

    for (size_t k = 0; k < sizeof(cases) / sizeof(cases[0]); ++k) {
        int status;
        lu     = (rs_chain_lu *)&lu; /* not NULL: symbolic must clear it */
        status = rs_chain_lu_symbolic_permuted(cases[k].n, cases[k].row_ptr, cases[k].cols,
                                               cases[k].perm, &lu);
        printf("    %-28s status %d\n", cases[k].what, status);
        CHECK(status == 1, "%s: status %d, expected 1", cases[k].what, status);
        CHECK(lu == NULL, "%s: *lu is NULL", cases[k].what);
    }
    /* The unbroken pattern is accepted (so the cases above fail for their defect). */
    CHECK(rs_chain_lu_symbolic(3, row_ptr, cols, &lu) == 0, "the tridiagonal pattern");
    rs_chain_lu_free(lu);
    rs_chain_lu_free(NULL);
}

/* ---- Rods with kinematic rows: the substitution before the chain ---------------------------- */

/* The shape of ph_director's Jacobian (src/formulations/ph_director/ph_director_element.f90):
   every node has positions q and velocities v of `components` unknowns each, then its
   multipliers; every element has `interior_size` stress unknowns between its nodes. Rows:
   - the kinematic row of q_c, R_K = q - q_n - h/2 (v + v_n): entries q_c (1) and v_c (-h/2)
     only, two entries;
   - the momentum row of v_c: dense random in the q of the nodes of its elements and in its
     elements' stresses, the transposed constraint gradient in the node's multipliers; in v
     only through the mass, v_c of the same component at the nodes of its elements (positive,
     the diagonal the largest);
   - a multiplier row: the constraint gradient, dense random in its node's q, and a zero
     diagonal (explicit for the first);
   - a stress row: dense random in the q of its element's nodes and in its element's stresses.
   The mass entries in v are h/2 times `mass` (times 1 + 0.25 u on the diagonal, 0.25 (1 + 0.25
   u) to the neighbours): substituting v_c = 2/h (q_c - b) puts them on q_c as `mass`, the
   diagonal of the generator above (M / h^2 of a dynamic rod), and the substitution's growth
   stays below 2 (kinematic_growth). Substituting q_c instead would fill: the stress,
   multiplier and other components' momentum rows hold q_c but not v_c. Variants:
   - third_entry: every kinematic row also has q_{c+1} (a random value), so that it has three
     entries and nothing is substituted: the panels of the whole matrix, for comparison;
   - rows_swapped: the kinematic row sits at v_c's index and the momentum row at q_c's, so
     the diagonal unknown of the two-entry row is v_c, the one to substitute;
   - fill_component c >= 0: at every node the momentum row of component c+1 holds v_c (a
     random entry of the mass's scale) but not q_c, so component c's kinematic rows fill
     whichever unknown is substituted. */
typedef struct {
    int    n_elements, components, node_multipliers, interior_size;
    double h, mass;
    int    third_entry, rows_swapped, fill_component;
} kinematic_shape_t;

static int kinematic_node_size(const kinematic_shape_t *s)
{
    return 2 * s->components + s->node_multipliers;
}

static int kinematic_q(const kinematic_shape_t *s, int node, int c)
{
    return node * (kinematic_node_size(s) + s->interior_size) + c;
}

static int kinematic_v(const kinematic_shape_t *s, int node, int c)
{
    return kinematic_q(s, node, c) + s->components;
}

static int kinematic_multiplier(const kinematic_shape_t *s, int node, int j)
{
    return kinematic_q(s, node, 0) + 2 * s->components + j;
}

static int kinematic_stress(const kinematic_shape_t *s, int element, int j)
{
    return kinematic_q(s, element, 0) + kinematic_node_size(s) + j;
}

static int kinematic_row(const kinematic_shape_t *s, int node, int c)
{
    return s->rows_swapped ? kinematic_v(s, node, c) : kinematic_q(s, node, c);
}

static int momentum_row(const kinematic_shape_t *s, int node, int c)
{
    return s->rows_swapped ? kinematic_q(s, node, c) : kinematic_v(s, node, c);
}

/* A stored entry (possibly 0.0) of a matrix being made. */
static void store_entry(rod_matrix_t *m, int i, int j, double value)
{
    m->a[i + (size_t)j * m->n]      = value;
    m->stored[i + (size_t)j * m->n] = 1;
}

static void kinematic_matrix_make(const kinematic_shape_t *s, uint64_t seed, rod_matrix_t *m)
{
    const int k = s->components, n = kinematic_q(s, s->n_elements + 1, 0) - s->interior_size;

    lcg_seed(seed);
    m->n      = n;
    m->a      = calloc((size_t)n * n, sizeof(double));
    m->stored = calloc((size_t)n * n, 1);
    for (int a = 0; a <= s->n_elements; ++a) {
        const int first = a > 0 ? a - 1 : 0, last = a < s->n_elements ? a + 1 : a;
        /* The constraint gradient: the multiplier rows in q and, transposed, the momentum rows
           in the multipliers (an unrelated random block there makes the saddle point's Schur
           complement nearly singular at random). */
        for (int j = 0; j < s->node_multipliers; ++j) {
            const int row = kinematic_multiplier(s, a, j);
            for (int d = 0; d < k; ++d) {
                const double g = lcg_uniform();
                store_entry(m, row, kinematic_q(s, a, d), g);
                store_entry(m, momentum_row(s, a, d), row, g);
            }
            if (j == 0) store_entry(m, row, row, 0.0);
        }
        for (int c = 0; c < k; ++c) {
            const int row = kinematic_row(s, a, c);
            store_entry(m, row, kinematic_q(s, a, c), 1.0);
            store_entry(m, row, kinematic_v(s, a, c), -s->h / 2.0);
            if (s->third_entry)
                store_entry(m, row, kinematic_q(s, a, (c + 1) % k), 0.5 * lcg_uniform());
        }
        for (int c = 0; c < k; ++c) {
            const int row = momentum_row(s, a, c);
            for (int b = first; b <= last; ++b) {
                const double mass = b == a ? 1.0 + 0.25 * lcg_uniform()
                                           : 0.25 * (1.0 + 0.25 * lcg_uniform());
                for (int d = 0; d < k; ++d)
                    store_entry(m, row, kinematic_q(s, b, d), lcg_uniform());
                store_entry(m, row, kinematic_v(s, b, c), s->h / 2.0 * s->mass * mass);
            }
            for (int e = a - 1; e <= a; ++e)
                if (e >= 0 && e < s->n_elements)
                    for (int j = 0; j < s->interior_size; ++j)
                        store_entry(m, row, kinematic_stress(s, e, j), lcg_uniform());
        }
        if (s->fill_component >= 0) {
            const int c = s->fill_component, row = momentum_row(s, a, (c + 1) % k);
            m->a[row + (size_t)kinematic_q(s, a, c) * n]      = 0.0;
            m->stored[row + (size_t)kinematic_q(s, a, c) * n] = 0;
            store_entry(m, row, kinematic_v(s, a, c), s->h / 2.0 * s->mass * 0.25 * lcg_uniform());
        }
    }
    for (int e = 0; e < s->n_elements; ++e)
        for (int i = 0; i < s->interior_size; ++i) {
            const int row = kinematic_stress(s, e, i);
            for (int b = e; b <= e + 1; ++b)
                for (int d = 0; d < k; ++d)
                    store_entry(m, row, kinematic_q(s, b, d), lcg_uniform());
            for (int j = 0; j < s->interior_size; ++j)
                store_entry(m, row, kinematic_stress(s, e, j),
                            lcg_uniform() + (i == j ? s->mass : 0.0));
        }
}

/* Sizes drawn from the seed as random_shape does: 4 to 12 components (4 to 6 for the long
   chain), more than the at most 3 multipliers (as many as the components fix a node's q by
   themselves, and such matrices measured 1e3 times worse conditioned); a time step h from
   1e-3 to 1 (log-uniform); the mass of random_shape for the random entries of a momentum row. */
static kinematic_shape_t kinematic_shape(int elements, uint64_t seed)
{
    kinematic_shape_t s;
    memset(&s, 0, sizeof(s));
    lcg_seed(seed + 2000);
    s.n_elements       = elements;
    s.components       = elements > 10 ? lcg_int(4, 6) : lcg_int(4, 12);
    s.node_multipliers = lcg_int(0, 3);
    s.interior_size    = elements > 10 ? lcg_int(4, 12) : lcg_int(4, 30);
    s.h                = pow(10.0, -3.0 * (0.5 * lcg_uniform() + 0.5));
    s.mass             = sqrt(3.0 * s.components + s.node_multipliers + 2.0 * s.interior_size);
    s.fill_component   = -1;
    return s;
}

/* The growth of the substitutions: x_e = b_i / a_ie - (a_ip / a_ie) x_p cancels terms |a_ip /
   a_ie| times x_p, and the rows r with column e receive A_re a_ip / a_ie in column p, so the
   rounding errors of the substitution are those of an elimination step with growth
   1 + max |a_ip / a_ie| |A_re| / ||A|| (its pivot is chosen by the pattern, not by size: the
   growth factor of Higham, Accuracy and Stability of Numerical Algorithms, ch. 9). The kept
   rows then carry the chain LU's backward error of the other tests relative to entries that
   large, so backward_bound times this factor bounds the backward error. Over the rows (node,
   component) that the generator makes substitutable (e = v_c, p = q_c). */
static double kinematic_growth(const kinematic_shape_t *s, const rod_matrix_t *m)
{
    const int n = m->n;
    double    largest = 0.0;

    for (int a = 0; a <= s->n_elements; ++a)
        for (int c = 0; c < s->components; ++c) {
            const int    i = kinematic_row(s, a, c), e = kinematic_v(s, a, c);
            const double ratio = fabs(m->a[i + (size_t)kinematic_q(s, a, c) * n]) /
                                 fabs(m->a[i + (size_t)e * n]);
            if (c == s->fill_component) continue;
            for (int r = 0; r < n; ++r)
                if (r != i && ratio * fabs(m->a[r + (size_t)e * n]) > largest)
                    largest = ratio * fabs(m->a[r + (size_t)e * n]);
        }
    return 1.0 + largest / norm_inf_matrix(m);
}

/* Flops of the panels one element each (its node's kept unknowns and its stresses) and the
   last node, coupled through the next node's q (the momentum rows of that node hold this
   element's q and stresses): printed beside the panels found, for comparison. */
static double kinematic_flops_per_element(const kinematic_shape_t *s)
{
    const double node = s->components + s->node_multipliers, element = node + s->interior_size;
    const double coupling = s->components;

    return s->n_elements * (2.0 / 3.0 * element * element * element +
                            2.0 * element * element * coupling +
                            2.0 * coupling * element * coupling) +
           2.0 / 3.0 * node * node * node;
}

/* ph_director's pattern: every kinematic row substitutes its velocity (the count), the panels
   are smaller and cost fewer flops than those of the same matrix with a third entry in every
   kinematic row (nothing substituted), and both solutions are dgesv's, from both ends of the
   chain. The growth of the substitutions is at most 2, so the bounds are the other tests'. */
static void test_kinematic_rows_are_substituted(void)
{
    char label[128];
    for (size_t k = 0; k < sizeof(element_counts) / sizeof(element_counts[0]); ++k)
        for (uint64_t seed = 71; seed <= 73; ++seed) {
            kinematic_shape_t s = kinematic_shape(element_counts[k], seed);
            const int         kinematic = (s.n_elements + 1) * s.components;
            rs_chain_lu_info  info[2], whole[2];
            rod_matrix_t      m;
            double            growth;

            kinematic_matrix_make(&s, seed, &m);
            snprintf(label, sizeof(label), "E=%d seed=%d (k %d, multipliers %d, interior %d, "
                     "h %.2g)", s.n_elements, (int)seed, s.components, s.node_multipliers,
                     s.interior_size, s.h);
            growth = kinematic_growth(&s, &m);
            printf("    substitution growth %.3f (1 + max |a_ip / a_ie| |A_re| / ||A||)\n",
                   growth);
            CHECK(growth <= 2.0, "%s: growth %.3f at most 2", label, growth);
            check_matrix_against_dense(&m, backward_bound, label, info);
            rod_matrix_free(&m);

            s.third_entry = 1;
            kinematic_matrix_make(&s, seed, &m);
            snprintf(label, sizeof(label), "E=%d seed=%d with a third entry", s.n_elements,
                     (int)seed);
            check_matrix_against_dense(&m, backward_bound, label, whole);
            rod_matrix_free(&m);
            snprintf(label, sizeof(label), "E=%d seed=%d", s.n_elements, (int)seed);

            for (int d = 0; d < 2; ++d) {
                const char *direction = d == 0 ? "forward" : "reversed";
                printf("    %s: substituted %d of %d kinematic rows (third entry: %d); largest "
                       "panel %d (third entry: %d), %.4g flops (%.4g, ratio %.3f; one panel "
                       "per element %.4g)\n", direction, info[d].substituted, kinematic,
                       whole[d].substituted, info[d].largest_panel, whole[d].largest_panel,
                       info[d].flops, whole[d].flops, info[d].flops / whole[d].flops,
                       kinematic_flops_per_element(&s));
                CHECK(info[d].substituted == kinematic, "%s %s: %d substituted, expected %d",
                      label, direction, info[d].substituted, kinematic);
                CHECK(whole[d].substituted == 0, "%s %s: %d substituted with three entries",
                      label, direction, whole[d].substituted);
                /* Fewer flops, not necessarily a smaller largest panel: the plan weighs
                   flops against a fixed cost per panel and may merge panels differently. */
                CHECK(info[d].flops < whole[d].flops,
                      "%s %s: %.4g flops fewer than without substitution (%.4g)", label,
                      direction, info[d].flops, whole[d].flops);
            }
        }
}

/* The kinematic row at v_c's index: its diagonal unknown v_c is the one that adds nothing, so
   it is substituted on the first try (q_c would fill), every one of them. */
static void test_substitution_on_the_diagonal(void)
{
    char label[128];
    for (size_t k = 0; k < sizeof(element_counts) / sizeof(element_counts[0]) - 1; ++k) {
        const uint64_t    seed = 81 + k;
        kinematic_shape_t s = kinematic_shape(element_counts[k], seed);
        const int         kinematic = (s.n_elements + 1) * s.components;
        rs_chain_lu_info  info[2];
        rod_matrix_t      m;

        s.rows_swapped = 1;
        kinematic_matrix_make(&s, seed, &m);
        snprintf(label, sizeof(label), "E=%d seed=%d kinematic rows on v's diagonal (k %d)",
                 s.n_elements, (int)seed, s.components);
        check_matrix_against_dense(&m, backward_bound, label, info);
        for (int d = 0; d < 2; ++d) {
            printf("    %s: substituted %d of %d\n", d == 0 ? "forward" : "reversed",
                   info[d].substituted, kinematic);
            CHECK(info[d].substituted == kinematic, "%s: %d substituted, expected %d", label,
                  info[d].substituted, kinematic);
        }
        rod_matrix_free(&m);
    }
}

/* Component c's kinematic rows fill either way (q_c is in the stress rows, v_c in a momentum
   row without q_c): they stay in the panels, the other components' are substituted. */
static void test_substitution_skipped_when_it_would_fill(void)
{
    char label[128];
    for (uint64_t seed = 91; seed <= 93; ++seed) {
        kinematic_shape_t s = kinematic_shape(5, seed);
        const int         expected = (s.n_elements + 1) * (s.components - 1);
        rs_chain_lu_info  info[2];
        rod_matrix_t      m;

        s.fill_component = (int)(seed % (uint64_t)s.components);
        kinematic_matrix_make(&s, seed, &m);
        snprintf(label, sizeof(label), "E=5 seed=%d component %d of %d fills", (int)seed,
                 s.fill_component, s.components);
        check_matrix_against_dense(&m, backward_bound, label, info);
        for (int d = 0; d < 2; ++d) {
            printf("    %s: substituted %d (expected %d)\n", d == 0 ? "forward" : "reversed",
                   info[d].substituted, expected);
            CHECK(info[d].substituted == expected, "%s: %d substituted, expected %d", label,
                  info[d].substituted, expected);
        }
        rod_matrix_free(&m);
    }
}

/* Numeric refuses the matrix from both ends (a non-zero status, never a solution). */
static void check_substitution_refused(const rod_matrix_t *m, const char *label)
{
    csr_t        c;
    rs_chain_lu *lu[2] = {NULL, NULL};
    int         *perm = reversed_order(m->n);

    csr_from(m, &c);
    CHECK(rs_chain_lu_symbolic(c.n, c.row_ptr, c.cols, &lu[0]) == 0, "%s: symbolic", label);
    CHECK(rs_chain_lu_symbolic_permuted(c.n, c.row_ptr, c.cols, perm, &lu[1]) == 0,
          "%s: symbolic reversed", label);
    for (int d = 0; d < 2; ++d) {
        int status;
        if (!lu[d]) continue;
        status = rs_chain_lu_numeric(lu[d], c.values, 1e-13);
        printf("    %s, %s: numeric returned %d\n", label, d == 0 ? "forward" : "reversed",
               status);
        CHECK(status != 0, "%s %s: refused, got %d", label, d == 0 ? "forward" : "reversed",
              status);
    }
    rs_chain_lu_free(lu[0]);
    rs_chain_lu_free(lu[1]);
    free(perm);
    csr_free(&c);
}

/* The pivot of the substitution is a_ie, the v_c entry (-h/2) of the kinematic row, since
   v_c is the unknown substituted. One row of a middle node with that entry an explicit zero
   (the matrix stays regular: q_c is fixed by the row, v_c by the momentum rows), or with
   |a_ip / a_ie| = 1e9 > 1e8, or a NaN partner: refused. With 1e6: accepted, and dgesv's
   solution within the growth of that ratio (kinematic_growth). With the partner a_ip = 0
   (the row fixes v_c alone): accepted and right with the bounds of the other tests. */
static void test_zero_substitution_pivot_is_refused(void)
{
    const uint64_t    seed = 101;
    kinematic_shape_t s = kinematic_shape(5, seed);
    const int         row = kinematic_row(&s, 2, 1), v = kinematic_v(&s, 2, 1);
    const int         q = kinematic_q(&s, 2, 1);
    rod_matrix_t      m;
    double            condition, growth;
    double           *b, *x;

    kinematic_matrix_make(&s, seed, &m);
    b = malloc((size_t)m.n * sizeof(double));
    x = malloc((size_t)m.n * sizeof(double));
    m.a[row + (size_t)v * m.n] = 0.0;
    random_right_hand_side(&m, b);
    dense_solve(&m, b, x, &condition);
    printf("    pivot a_ie = 0: condition estimate of the matrix %.3g\n", condition);
    CHECK(condition < 1e10, "a_ie = 0: the matrix is regular (condition %.3g)", condition);
    check_substitution_refused(&m, "a_ie = 0");

    m.a[row + (size_t)v * m.n] = -1e-9 * m.a[row + (size_t)q * m.n];
    check_substitution_refused(&m, "|a_ip / a_ie| = 1e9");

    m.a[row + (size_t)v * m.n] = -s.h / 2.0;
    m.a[row + (size_t)q * m.n] = NAN;
    check_substitution_refused(&m, "a_ip = NaN");

    m.a[row + (size_t)q * m.n] = 1.0;
    m.a[row + (size_t)v * m.n] = -1e-6;
    growth = kinematic_growth(&s, &m);
    printf("    |a_ip / a_ie| = 1e6: substitution growth %.4g\n", growth);
    check_matrix_against_dense(&m, backward_bound * growth, "|a_ip / a_ie| = 1e6", NULL);

    m.a[row + (size_t)v * m.n] = -s.h / 2.0;
    m.a[row + (size_t)q * m.n] = 0.0;
    check_matrix_against_dense(&m, backward_bound, "a_ip = 0", NULL);
    free(b);
    free(x);
    rod_matrix_free(&m);
}

/* x = b: the same solution, bit for bit, as with separate arrays. The kinematic rows are at
   q_c's index, which is also a kept column: the solve must read b_i before it writes x_q. */
static void test_solve_in_place_with_substitution(void)
{
    for (int swapped = 0; swapped < 2; ++swapped) {
        const uint64_t    seed = 111 + (uint64_t)swapped;
        kinematic_shape_t s = kinematic_shape(5, seed);
        rod_matrix_t      m;
        csr_t             c;
        rs_chain_lu      *lu[2] = {NULL, NULL};
        int              *perm;
        double           *b, *x, *in_place;
        char              what[96];

        s.rows_swapped = swapped;
        kinematic_matrix_make(&s, seed, &m);
        csr_from(&m, &c);
        perm     = reversed_order(m.n);
        b        = malloc((size_t)m.n * sizeof(double));
        x        = malloc((size_t)m.n * sizeof(double));
        in_place = malloc((size_t)m.n * sizeof(double));
        random_right_hand_side(&m, b);
        CHECK(rs_chain_lu_symbolic(c.n, c.row_ptr, c.cols, &lu[0]) == 0, "symbolic");
        CHECK(rs_chain_lu_symbolic_permuted(c.n, c.row_ptr, c.cols, perm, &lu[1]) == 0,
              "symbolic reversed");
        for (int d = 0; d < 2; ++d) {
            const char      *direction = d == 0 ? "forward" : "reversed";
            rs_chain_lu_info info;
            double           difference = 0.0;
            int              status;
            if (!lu[d]) continue;
            rs_chain_lu_get_info(lu[d], &info);
            status = rs_chain_lu_numeric(lu[d], c.values, 1e-13);
            CHECK(status == 0, "%s: numeric returned %d", direction, status);
            if (status != 0) continue;
            rs_chain_lu_solve(lu[d], b, x);
            memcpy(in_place, b, (size_t)m.n * sizeof(double));
            rs_chain_lu_solve(lu[d], in_place, in_place);
            for (int i = 0; i < m.n; ++i)
                if (!(fabs(in_place[i] - x[i]) <= difference))
                    difference = fabs(in_place[i] - x[i]);
            snprintf(what, sizeof(what), "%s, %s: backward error",
                     swapped ? "rows swapped" : "kinematic rows at q", direction);
            printf("    %s, %s: %d substituted, max |x_in_place - x| = %.3g\n",
                   swapped ? "rows swapped" : "kinematic rows at q", direction,
                   info.substituted, difference);
            CHECK(info.substituted > 0, "%s: the substitution is used", direction);
            CHECK(memcmp(in_place, x, (size_t)m.n * sizeof(double)) == 0,
                  "%s: in place equal to separate arrays (max difference %.3g)", direction,
                  difference);
            CHECK_BELOW(backward_error(&m, x, b), backward_bound, what);
        }
        rs_chain_lu_free(lu[0]);
        rs_chain_lu_free(lu[1]);
        free(perm);
        free(b);
        free(x);
        free(in_place);
        csr_free(&c);
        rod_matrix_free(&m);
    }
}

int main(void)
{
    run_test("rods_match_dense_lu", test_rods_match_dense_lu);
    run_test("saddle_rows_match_dense_lu", test_saddle_rows_match_dense_lu);
    run_test("raw_random_blocks_match_dense_lu", test_raw_random_blocks_match_dense_lu);
    run_test("one_sided_coupling_matches_dense_lu", test_one_sided_coupling_matches_dense_lu);
    run_test("panels_follow_the_chain", test_panels_follow_the_chain);
    run_test("refactor_and_solve_in_place", test_refactor_and_solve_in_place);
    run_test("no_floating_point_exceptions", test_no_floating_point_exceptions);
    run_test("first_panel_singular_from_start_only", test_first_panel_singular_from_start_only);
    run_test("singular_matrices_are_refused", test_singular_matrices_are_refused);
    run_test("bad_patterns_are_rejected", test_bad_patterns_are_rejected);
    run_test("kinematic_rows_are_substituted", test_kinematic_rows_are_substituted);
    run_test("substitution_on_the_diagonal", test_substitution_on_the_diagonal);
    run_test("substitution_skipped_when_it_would_fill",
             test_substitution_skipped_when_it_would_fill);
    run_test("zero_substitution_pivot_is_refused", test_zero_substitution_pivot_is_refused);
    run_test("solve_in_place_with_substitution", test_solve_in_place_with_substitution);
    printf("%d passed, %d failed\n", n_passed, n_failed);
    return n_failed > 0 ? 1 : 0;
}
