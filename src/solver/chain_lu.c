/* The chain LU (interface and method in include/rs_chain_lu.h).

   Layout: panel k holds the unknowns [start[k], start[k+1]) of the chain order (size b_k).
   Its dense blocks, column-major, live in one array `values`:
     D_k  b_k x b_k        A_kk, then its LU factors (LAPACK getrf, pivots in ipiv),
     E_k  b_k x |C_k|      A_{k,k+1} restricted to the columns C_k,
     Ft_k b_k x |R_k|      A_{k+1,k} restricted to the rows R_k, transposed.
   C_k and R_k are local indices in panel k+1. The coupling F_k D_k^{-1} E_k is formed from
   the cheaper side: with fewer rows than columns (|R_k| < |C_k|, "left") D_k^{-T} is applied
   to Ft_k, else ("right") D_k^{-1} to E_k, each in place; the solve then applies D_k^{-1} in
   the backward or in the forward sweep along the chain. */
#include "rs_chain_lu.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* LAPACK and BLAS (OpenBLAS serial through Debian's alternatives, DESIGN.md §3). */
extern void dgetrf_(const int *m, const int *n, double *a, const int *lda, int *ipiv, int *info);
extern void dgetrs_(const char *trans, const int *n, const int *nrhs, const double *a,
                    const int *lda, const int *ipiv, double *b, const int *ldb, int *info);
extern void dgemm_(const char *transa, const char *transb, const int *m, const int *n,
                   const int *k, const double *alpha, const double *a, const int *lda,
                   const double *b, const int *ldb, const double *beta, double *c,
                   const int *ldc);
extern void dgemv_(const char *trans, const int *m, const int *n, const double *alpha,
                   const double *a, const int *lda, const double *x, const int *incx,
                   const double *beta, double *y, const int *incy);

typedef struct chain_core chain_core;

/* The chain LU of the kept unknowns (after the pre-elimination, see below). */
struct chain_core {
    int     n, nnz, n_panels;
    int    *start;     /* n_panels + 1 panel boundaries (chain positions) */
    int    *perm;      /* chain position -> unknown (NULL: the identity) */
    int    *n_cols;    /* |C_k|, k < n_panels - 1 */
    int    *n_rows;    /* |R_k| */
    int    *col_first; /* first local index of C_k if C_k is a contiguous range, else -1 */
    int    *row_first;
    int    *left;      /* the coupling of panel k was formed as (F_k D_k^{-1}) E_k */
    int    *col_index; /* C_k, from col_index + index_off[k] */
    int    *row_index; /* R_k, from row_index + index_off[k] */
    int    *index_off;
    size_t *d_off, *x_off, *f_off;
    size_t  n_values;
    double *values;
    int    *ipiv;   /* n: LAPACK pivots of each D_k, 1-based within its panel */
    size_t *dest;   /* nnz: where each entry of the pattern goes in values */
    double *column; /* largest entry of each column of the panel being factored */
    double *work;   /* the coupling product F_k X_k, or a gathered vector */
    double *z;      /* n: the solve in chain order */
    double  flops;
    int     largest_panel, widest_coupling;
    int    *row_ptr, *cols; /* the pattern (place_entries) */
    int    *inverse;        /* unknown -> chain position (NULL: the identity) */
    int    *min_nb, *max_nb; /* neighbours of each chain position (find_panels) */
    char   *forbidden;      /* cuts of plans that failed (core_replan) */
    int     replans;
};

/* Everything place_entries makes from the panels. */
static void free_plan(chain_core *lu)
{
    free(lu->n_cols);
    free(lu->n_rows);
    free(lu->col_first);
    free(lu->row_first);
    free(lu->left);
    free(lu->col_index);
    free(lu->row_index);
    free(lu->index_off);
    free(lu->d_off);
    free(lu->x_off);
    free(lu->f_off);
    free(lu->values);
    free(lu->ipiv);
    free(lu->dest);
    free(lu->column);
    free(lu->work);
    free(lu->z);
    lu->n_cols = lu->n_rows = lu->col_first = lu->row_first = lu->left = NULL;
    lu->col_index = lu->row_index = lu->index_off = NULL;
    lu->d_off = lu->x_off = lu->f_off = lu->dest = NULL;
    lu->values = lu->column = lu->work = lu->z = NULL;
    lu->ipiv = NULL;
}

static void core_free(chain_core *lu)
{
    if (!lu) return;
    free_plan(lu);
    free(lu->start);
    free(lu->perm);
    free(lu->inverse);
    free(lu->row_ptr);
    free(lu->cols);
    free(lu->min_nb);
    free(lu->max_nb);
    free(lu->forbidden);
    free(lu);
}

/* Flops of a panel of s unknowns whose Schur complement reaches f unknowns of the next one:
   getrf, one getrs with f right-hand sides, and the f x s x f product. */
static double panel_flops(double s, double f)
{
    return 2.0 / 3.0 * s * s * s + 2.0 * s * s * f + 2.0 * s * f * f;
}

/* What a panel costs beyond its flops (the calls to LAPACK and BLAS), in flops, so that tiny
   panels are merged: measured best of 0, 5e3 and 2e4 on se3_pg's cantilever (nodes of 6
   unknowns: 2.9, 3.0 and 3.2 us per element and Newton iteration at 1024 elements), neutral on
   ph_director's panels of 48. */
static const double panel_overhead = 5e3;

/* Panels from the symmetrized pattern in chain order (minimum and maximum neighbour of every
   position, itself included). Cutting at a and b makes [a, b) a panel; the matrix is block
   tridiagonal if and only if every panel reaches past everything before it couples to,
   reach(a) < b with reach(a) the largest neighbour of the positions before a. Among such
   cuts a dynamic programme takes those of the fewest flops, over candidate cuts where the
   front (the positions at or after a cut coupled to one before it) is a local minimum: a
   node between two elements' interiors, for a rod. Panels are at most `widest` long, three
   bandwidths: a longer one never pays (its flops grow as the cube). Returns 3 if no such
   partition exists (the pattern is not a chain in this order). */
static int find_panels(chain_core *lu)
{
    const int  n = lu->n;
    const int *min_nb = lu->min_nb, *max_nb = lu->max_nb;
    int      *front = NULL, *diff = NULL, *reach = NULL, *cut = NULL, *from = NULL;
    double   *best = NULL;
    int       n_cuts = 0, bandwidth = 0, widest, status = 0, m = 0;

    front = calloc((size_t)n + 2, sizeof(int));
    diff  = calloc((size_t)n + 2, sizeof(int));
    reach = malloc(((size_t)n + 1) * sizeof(int));
    cut   = malloc(((size_t)n + 1) * sizeof(int));
    from  = malloc(((size_t)n + 1) * sizeof(int));
    best  = malloc(((size_t)n + 1) * sizeof(double));
    if (!front || !diff || !reach || !cut || !from || !best) {
        status = 2;
        goto done;
    }
    for (int j = 0; j < n; ++j) {
        if (min_nb[j] < j) {
            diff[min_nb[j] + 1] += 1;
            diff[j + 1] -= 1;
        }
        if (max_nb[j] - j > bandwidth) bandwidth = max_nb[j] - j;
    }
    for (int p = 0, count = 0; p <= n; ++p) {
        count += diff[p];
        front[p] = count;
    }
    reach[0] = -1;
    for (int p = 0; p < n; ++p) reach[p + 1] = max_nb[p] > reach[p] ? max_nb[p] : reach[p];
    widest   = 3 * (bandwidth + 1) > 64 ? 3 * (bandwidth + 1) : 64;
    /* Candidate cuts: the local minima of the front; after a failed plan every position but
       the cuts that failed (core_replan). */
    cut[n_cuts++] = 0;
    if (lu->replans > 0) {
        for (int p = 1; p < n; ++p)
            if (!lu->forbidden[p]) cut[n_cuts++] = p;
    } else {
        /* A node between two elements is crossed by that node's unknowns only: the narrowest
           minima. A minimum crossed by far more (inside the last element, where the front
           runs down to the end) cuts an element apart, which a quasistatic rod's free end
           cannot take (its part of the element alone is singular). */
        int narrowest = n;
        for (int p = 1; p < n; ++p)
            if (front[p] < front[p - 1] && front[p] <= front[p + 1] && front[p] < narrowest)
                narrowest = front[p];
        for (int p = 1; p < n; ++p)
            if (front[p] < front[p - 1] && front[p] <= front[p + 1] &&
                front[p] <= 2 * narrowest + 4)
                cut[n_cuts++] = p;
    }
    cut[n_cuts++] = n;
    best[0] = 0.0;
    for (int j = 1; j < n_cuts; ++j) {
        const int b = cut[j];
        best[j]     = HUGE_VAL;
        from[j]     = -1;
        for (int i = j - 1; i >= 0 && b - cut[i] <= widest; --i) {
            const int a = cut[i];
            if (best[i] < HUGE_VAL && reach[a] < b) {
                const double cost =
                    best[i] + panel_overhead + panel_flops(b - a, b < n ? front[b] : 0);
                if (cost < best[j]) {
                    best[j] = cost;
                    from[j] = i;
                }
            }
        }
    }
    if (from[n_cuts - 1] < 0 && n > widest) {
        status = 3;
        goto done;
    }
    /* Walk back from n; a pattern shorter than `widest` is at worst one dense panel. */
    lu->start = malloc(((size_t)n_cuts + 1) * sizeof(int));
    if (!lu->start) {
        status = 2;
        goto done;
    }
    if (from[n_cuts - 1] < 0) {
        lu->start[m++] = n;
        lu->start[m++] = 0;
    } else {
        for (int j = n_cuts - 1; j >= 0; j = from[j]) {
            lu->start[m++] = cut[j];
            if (j == 0) break;
        }
    }
    for (int i = 0; i < m / 2; ++i) {
        const int t          = lu->start[i];
        lu->start[i]         = lu->start[m - 1 - i];
        lu->start[m - 1 - i] = t;
    }
    lu->n_panels = m - 1;
done:
    free(front);
    free(diff);
    free(reach);
    free(cut);
    free(from);
    free(best);
    return status;
}

/* C_k and R_k from the (unsymmetrized) pattern, the offsets of the blocks, and the place of
   every entry. Returns 1 if an entry couples panels further apart than neighbours. */
static int place_entries(chain_core *lu)
{
    const int  n = lu->n, m = lu->n_panels;
    const int *row_ptr = lu->row_ptr, *cols = lu->cols, *inverse = lu->inverse;
    int      *panel_of = malloc((size_t)n * sizeof(int));
    int      *col_pos  = malloc((size_t)n * sizeof(int));
    int      *row_pos  = malloc((size_t)n * sizeof(int));
    int       status   = 0, work = 1;
    size_t    offset   = 0;

    lu->n_cols    = calloc((size_t)m, sizeof(int));
    lu->n_rows    = calloc((size_t)m, sizeof(int));
    lu->col_first = malloc((size_t)m * sizeof(int));
    lu->row_first = malloc((size_t)m * sizeof(int));
    lu->left      = calloc((size_t)m, sizeof(int));
    lu->index_off = calloc((size_t)m + 1, sizeof(int));
    lu->col_index = malloc((size_t)n * sizeof(int));
    lu->row_index = malloc((size_t)n * sizeof(int));
    lu->d_off     = malloc((size_t)m * sizeof(size_t));
    lu->x_off     = malloc((size_t)m * sizeof(size_t));
    lu->f_off     = malloc((size_t)m * sizeof(size_t));
    lu->dest      = malloc(((size_t)lu->nnz + 1) * sizeof(size_t));
    if (!panel_of || !col_pos || !row_pos || !lu->n_cols || !lu->n_rows || !lu->col_first ||
        !lu->row_first || !lu->left || !lu->index_off || !lu->col_index || !lu->row_index || !lu->d_off ||
        !lu->x_off || !lu->f_off || !lu->dest) {
        status = 2;
        goto done;
    }
    for (int k = 0; k < m; ++k)
        for (int p = lu->start[k]; p < lu->start[k + 1]; ++p) panel_of[p] = k;
    for (int p = 0; p < n; ++p) col_pos[p] = row_pos[p] = -1;
    /* Mark the coupled columns and rows of each next panel, in chain position order. */
    for (int i = 0; i < n; ++i) {
        const int pi = inverse ? inverse[i] : i;
        for (int e = row_ptr[i]; e < row_ptr[i + 1]; ++e) {
            const int pj = inverse ? inverse[cols[e]] : cols[e], gap = panel_of[pj] - panel_of[pi];
            if (gap > 1 || gap < -1) {
                status = 1;
                goto done;
            }
            if (gap == 1) col_pos[pj] = 0;  /* in C of panel_of[pi] */
            if (gap == -1) row_pos[pi] = 0; /* in R of panel_of[pj] */
        }
    }
    for (int k = 0; k + 1 < m; ++k) {
        const int s = lu->start[k + 1], e = lu->start[k + 2];
        int       nc = 0, nr = 0;
        for (int p = s; p < e; ++p) {
            if (col_pos[p] >= 0) {
                lu->col_index[lu->index_off[k] + nc] = p - s;
                col_pos[p]                           = nc++;
            }
            if (row_pos[p] >= 0) {
                lu->row_index[lu->index_off[k] + nr] = p - s;
                row_pos[p]                           = nr++;
            }
        }
        lu->n_cols[k]        = nc;
        lu->n_rows[k]        = nr;
        lu->index_off[k + 1] = lu->index_off[k] + (e - s);
        lu->col_first[k] = nc > 0 && lu->col_index[lu->index_off[k] + nc - 1] -
                                             lu->col_index[lu->index_off[k]] == nc - 1
                               ? lu->col_index[lu->index_off[k]]
                               : -1;
        lu->row_first[k] = nr > 0 && lu->row_index[lu->index_off[k] + nr - 1] -
                                             lu->row_index[lu->index_off[k]] == nr - 1
                               ? lu->row_index[lu->index_off[k]]
                               : -1;
    }
    lu->n_cols[m - 1] = lu->n_rows[m - 1] = 0;
    lu->col_first[m - 1] = lu->row_first[m - 1] = -1;
    lu->flops = 0.0;
    lu->largest_panel = lu->widest_coupling = 0;
    for (int k = 0; k < m; ++k) {
        const int b = lu->start[k + 1] - lu->start[k], c = lu->n_cols[k], r = lu->n_rows[k];
        lu->d_off[k] = offset;
        offset += (size_t)b * (size_t)b;
        lu->x_off[k] = offset;
        offset += (size_t)b * (size_t)c;
        lu->f_off[k] = offset;
        offset += (size_t)r * (size_t)b;
        lu->left[k] = r < c;
        lu->flops += 2.0 / 3.0 * b * (double)b * b + 2.0 * b * (double)b * (r < c ? r : c) +
                     2.0 * r * (double)b * c;
        if (b > lu->largest_panel) lu->largest_panel = b;
        if (c > lu->widest_coupling) lu->widest_coupling = c;
        if (r > lu->widest_coupling) lu->widest_coupling = r;
        if (r * c > work) work = r * c;
        if (b > work) work = b;
        if (c > work) work = c;
        if (r > work) work = r;
    }
    lu->n_values = offset;
    lu->values   = malloc((offset > 0 ? offset : 1) * sizeof(double));
    lu->work     = malloc((size_t)work * sizeof(double));
    lu->column   = malloc(((size_t)lu->largest_panel + 1) * sizeof(double));
    lu->ipiv     = malloc(((size_t)n + 1) * sizeof(int));
    lu->z        = malloc(((size_t)n + 1) * sizeof(double));
    if (!lu->values || !lu->work || !lu->column || !lu->ipiv || !lu->z) {
        status = 2;
        goto done;
    }
    for (int i = 0; i < n; ++i) {
        const int pi = inverse ? inverse[i] : i, P = panel_of[pi];
        for (int e = row_ptr[i]; e < row_ptr[i + 1]; ++e) {
            const int pj = inverse ? inverse[cols[e]] : cols[e], Q = panel_of[pj];
            const size_t bP = (size_t)(lu->start[P + 1] - lu->start[P]);
            if (Q == P) {
                lu->dest[e] = lu->d_off[P] + (size_t)(pi - lu->start[P]) +
                              (size_t)(pj - lu->start[P]) * bP;
            } else if (Q == P + 1) {
                lu->dest[e] = lu->x_off[P] + (size_t)(pi - lu->start[P]) + (size_t)col_pos[pj] * bP;
            } else {
                lu->dest[e] = lu->f_off[Q] + (size_t)(pj - lu->start[Q]) +
                              (size_t)row_pos[pi] * (size_t)(lu->start[Q + 1] - lu->start[Q]);
            }
        }
    }
done:
    free(panel_of);
    free(col_pos);
    free(row_pos);
    return status;
}

static int core_symbolic(int n, const int *row_ptr, const int *cols, const int *perm,
                                  chain_core **result)
{
    chain_core *lu;
    int         *min_nb = NULL, *max_nb = NULL, *inverse = NULL, status = 0;

    *result = NULL;
    if (n < 1 || !row_ptr || !cols || row_ptr[0] != 0) return 1;
    for (int i = 0; i < n; ++i) {
        if (row_ptr[i + 1] < row_ptr[i]) return 1;
        for (int e = row_ptr[i]; e < row_ptr[i + 1]; ++e)
            if (cols[e] < 0 || cols[e] >= n) return 1;
    }
    lu = calloc(1, sizeof(*lu));
    if (!lu) return 2;
    lu->n   = n;
    lu->nnz = row_ptr[n];
    min_nb  = malloc((size_t)n * sizeof(int));
    max_nb  = malloc((size_t)n * sizeof(int));
    if (perm) {
        lu->perm = malloc((size_t)n * sizeof(int));
        inverse  = malloc((size_t)n * sizeof(int));
    }
    if (!min_nb || !max_nb || (perm && (!lu->perm || !inverse))) {
        status = 2;
        goto done;
    }
    if (perm) {
        for (int p = 0; p < n; ++p) inverse[p] = -1;
        for (int p = 0; p < n; ++p) {
            if (perm[p] < 0 || perm[p] >= n || inverse[perm[p]] >= 0) {
                status = 1;
                goto done;
            }
            lu->perm[p]      = perm[p];
            inverse[perm[p]] = p;
        }
    }
    for (int p = 0; p < n; ++p) min_nb[p] = max_nb[p] = p;
    for (int i = 0; i < n; ++i) {
        const int pi = inverse ? inverse[i] : i;
        for (int e = row_ptr[i]; e < row_ptr[i + 1]; ++e) {
            const int pj = inverse ? inverse[cols[e]] : cols[e];
            if (pj < min_nb[pi]) min_nb[pi] = pj;
            if (pj > max_nb[pi]) max_nb[pi] = pj;
            if (pi < min_nb[pj]) min_nb[pj] = pi;
            if (pi > max_nb[pj]) max_nb[pj] = pi;
        }
    }
    lu->row_ptr   = malloc(((size_t)n + 1) * sizeof(int));
    lu->cols      = malloc(((size_t)lu->nnz + 1) * sizeof(int));
    lu->forbidden = calloc((size_t)n + 1, 1);
    if (!lu->row_ptr || !lu->cols || !lu->forbidden) {
        status = 2;
        goto done;
    }
    lu->min_nb = min_nb;
    lu->max_nb = max_nb;
    min_nb = max_nb = NULL;
    status = find_panels(lu);
    if (status) goto done;
    memcpy(lu->row_ptr, row_ptr, ((size_t)n + 1) * sizeof(int));
    memcpy(lu->cols, cols, (size_t)lu->nnz * sizeof(int));
    lu->inverse = inverse;
    inverse     = NULL;
    status      = place_entries(lu);
done:
    free(min_nb);
    free(max_nb);
    free(inverse);
    if (status) core_free(lu);
    else *result = lu;
    return status;
}


/* Plan the panels again without any cut of the current plan (a panel of it was singular on
   its own: a constrained rod, whose element constraint rows need both end nodes, is regular
   only with the cuts after the nodes instead of before them), among all positions. */
static int core_replan(chain_core *lu)
{
    int *start = lu->start, n_panels = lu->n_panels, status;

    if (n_panels < 2) return 1;
    /* A cut within the coupling of a failed one leaves the same unknowns out of the leading
       block, give or take a few: forbid those too. */
    for (int k = 1; k < n_panels; ++k) {
        const int width = lu->n_cols[k - 1] > lu->n_rows[k - 1] ? lu->n_cols[k - 1]
                                                                : lu->n_rows[k - 1];
        for (int p = start[k] - width; p <= start[k] + width; ++p)
            if (p > 0 && p < lu->n) lu->forbidden[p] = 1;
    }
    ++lu->replans;
    lu->start = NULL;
    status    = find_panels(lu);
    if (status) {
        /* No other plan: the current one stays usable. */
        free(lu->start);
        lu->start    = start;
        lu->n_panels = n_panels;
        return status == 2 ? 2 : 3;
    }
    free(start);
    free_plan(lu);
    return place_entries(lu);
}

static void core_get_info(const chain_core *lu, rs_chain_lu_info *info)
{
    info->n_panels        = lu->n_panels;
    info->largest_panel   = lu->largest_panel;
    info->widest_coupling = lu->widest_coupling;
    info->flops           = lu->flops;
    info->doubles         = (double)lu->n_values;
    info->replans         = lu->replans;
}

static int core_numeric(chain_core *lu, const double *values, double pivot_tol)
{
    static const double one = 1.0, minus_one = -1.0, zero = 0.0;
    const int           m   = lu->n_panels;

    memset(lu->values, 0, lu->n_values * sizeof(double));
    for (int e = 0; e < lu->nnz; ++e) lu->values[lu->dest[e]] = values[e];
    for (int k = 0; k < m; ++k) {
        const int b = lu->start[k + 1] - lu->start[k], c = lu->n_cols[k], r = lu->n_rows[k];
        double   *D = lu->values + lu->d_off[k];
        int      *ipiv = lu->ipiv + lu->start[k], info = 0;

        for (int j = 0; j < b; ++j) {
            double largest = 0.0;
            for (int i = 0; i < b; ++i) {
                const double a = fabs(D[i + (size_t)j * b]);
                if (a > largest) largest = a;
            }
            lu->column[j] = largest;
        }
        dgetrf_(&b, &b, D, &b, ipiv, &info);
        if (info != 0) return k + 1;
        /* A pivot that cancelled down to round-off of its column: D_k is singular to working
           precision (the matrix may not be; pivoting across panels would be needed). NaN
           fails the test too. */
        for (int j = 0; j < b; ++j)
            if (!(fabs(D[j + (size_t)j * b]) > pivot_tol * lu->column[j])) return k + 1;
        if (k + 1 < m && c > 0 && r > 0) {
            const int bn = lu->start[k + 2] - lu->start[k + 1];
            double   *E = lu->values + lu->x_off[k], *Ft = lu->values + lu->f_off[k];
            double   *next = lu->values + lu->d_off[k + 1];
            if (lu->left[k]) dgetrs_("T", &b, &r, D, &b, ipiv, Ft, &b, &info);
            else dgetrs_("N", &b, &c, D, &b, ipiv, E, &b, &info);
            if (lu->row_first[k] >= 0 && lu->col_first[k] >= 0) {
                double *target = next + lu->row_first[k] + (size_t)lu->col_first[k] * bn;
                dgemm_("T", "N", &r, &c, &b, &minus_one, Ft, &b, E, &b, &one, target, &bn);
            } else {
                const int *rows = lu->row_index + lu->index_off[k];
                const int *cols = lu->col_index + lu->index_off[k];
                dgemm_("T", "N", &r, &c, &b, &one, Ft, &b, E, &b, &zero, lu->work, &r);
                for (int j = 0; j < c; ++j)
                    for (int i = 0; i < r; ++i)
                        next[rows[i] + (size_t)cols[j] * bn] -= lu->work[i + (size_t)j * r];
            }
        }
    }
    return 0;
}

static void core_solve(chain_core *lu, const double *b_in, double *x)
{
    static const double one = 1.0, minus_one = -1.0;
    static const int    inc = 1;
    const int           m = lu->n_panels, n = lu->n;
    double             *z = lu->z;
    int                 info = 0;

    for (int p = 0; p < n; ++p) z[p] = b_in[lu->perm ? lu->perm[p] : p];
    /* Forward: y_{k+1}[R_k] -= F_k D_k^{-1} y_k, with D_k^{-1} applied here on the right
       panels (z_k becomes D_k^{-1} y_k) and already inside Ft_k on the left ones. */
    for (int k = 0; k < m; ++k) {
        const int b = lu->start[k + 1] - lu->start[k], r = lu->n_rows[k];
        double   *zk = z + lu->start[k];
        if (!lu->left[k])
            dgetrs_("N", &b, &inc, lu->values + lu->d_off[k], &b, lu->ipiv + lu->start[k], zk,
                    &b, &info);
        if (k + 1 < m && r > 0) {
            const double *Ft   = lu->values + lu->f_off[k];
            double       *next = z + lu->start[k + 1];
            if (lu->row_first[k] >= 0) {
                dgemv_("T", &b, &r, &minus_one, Ft, &b, zk, &inc, &one, next + lu->row_first[k],
                       &inc);
            } else {
                const int   *rows = lu->row_index + lu->index_off[k];
                const double zero = 0.0;
                dgemv_("T", &b, &r, &one, Ft, &b, zk, &inc, &zero, lu->work, &inc);
                for (int i = 0; i < r; ++i) next[rows[i]] -= lu->work[i];
            }
        }
    }
    /* Backward: x_k = D_k^{-1} (y_k - E_k x_{k+1}[C_k]) on the left panels, and
       x_k = D_k^{-1} y_k - (D_k^{-1} E_k) x_{k+1}[C_k] on the right ones. */
    for (int k = m - 1; k >= 0; --k) {
        const int b = lu->start[k + 1] - lu->start[k], c = lu->n_cols[k];
        double   *zk = z + lu->start[k];
        if (k + 1 < m && c > 0) {
            const double *next = z + lu->start[k + 1], *g = next;
            if (lu->col_first[k] >= 0) {
                g = next + lu->col_first[k];
            } else {
                const int *cols = lu->col_index + lu->index_off[k];
                for (int j = 0; j < c; ++j) lu->work[j] = next[cols[j]];
                g = lu->work;
            }
            dgemv_("N", &b, &c, &minus_one, lu->values + lu->x_off[k], &b, g, &inc, &one, zk,
                   &inc);
        }
        if (lu->left[k])
            dgetrs_("N", &b, &inc, lu->values + lu->d_off[k], &b, lu->ipiv + lu->start[k], zk,
                    &b, &info);
    }
    for (int p = 0; p < n; ++p) x[lu->perm ? lu->perm[p] : p] = z[p];
}

/* ---- Substitution rows, eliminated before the chain ----------------------------------------
   A row i with two entries, in columns e and p, says a_ie x_e + a_ip x_p = b_i: the unknown
   x_e = (b_i - a_ip x_p) / a_ie is substituted into every other row before the chain is
   factored, A'_rp = A_rp - A_re a_ip / a_ie and b'_r = b_r - A_re b_i / a_ie, and row i and
   column e leave the system. It is taken only where every other row with column e has column p
   too (nothing is added to the pattern), e being the diagonal unknown i if that holds for it,
   else the other one. ph_director's kinematic rows R_K = q_{n+1} - q_n - h/2 (v_{n+1} + v_n)
   (methods/ph_director_3d.md §5.6) are such rows, eliminating v_{n+1} (the momentum rows hold
   v only through the mass): the 24 velocities of a panel's two nodes leave its 72 unknowns,
   a third of the flops of its LU. This is a pivot order of the same LU, not the condensed
   step of §5.5: the Newton residual is still the whole one. */

struct rs_chain_lu {
    int         n, n_kept, n_elim, n_updates;
    int        *kept_row, *kept_col; /* row and column at each kept position */
    int        *elim_row, *elim_col; /* the substitution rows i and their unknowns e */
    int        *elim_partner;        /* kept position of the partner column p */
    int        *elim_pivot, *elim_off; /* positions of a_ie and a_ip in the values */
    int        *entry_src;   /* position in the values of each entry of the kept matrix */
    int        *update_src;  /* position of A_re */
    int        *update_dst;  /* entry (r, p) of the kept matrix */
    int        *update_elim; /* which substitution (index into elim_*) */
    int        *update_row;  /* kept position of r */
    double     *inverse_pivot, *ratio, *coefficient; /* 1 / a_ie, a_ip / a_ie, A_re / a_ie */
    double     *kept_values, *b_kept, *x_kept, *x_elim;
    chain_core *core;
};

void rs_chain_lu_free(rs_chain_lu *lu)
{
    if (!lu) return;
    core_free(lu->core);
    free(lu->kept_row);
    free(lu->kept_col);
    free(lu->elim_row);
    free(lu->elim_col);
    free(lu->elim_partner);
    free(lu->elim_pivot);
    free(lu->elim_off);
    free(lu->entry_src);
    free(lu->update_src);
    free(lu->update_dst);
    free(lu->update_elim);
    free(lu->update_row);
    free(lu->inverse_pivot);
    free(lu->ratio);
    free(lu->coefficient);
    free(lu->kept_values);
    free(lu->b_kept);
    free(lu->x_kept);
    free(lu->x_elim);
    free(lu);
}

/* Position of column c in row r of a pattern with sorted columns, or -1. */
static int find_entry(const int *row_ptr, const int *cols, int r, int c)
{
    int lo = row_ptr[r], hi = row_ptr[r + 1] - 1;
    while (lo <= hi) {
        const int mid = (lo + hi) / 2;
        if (cols[mid] == c) return mid;
        if (cols[mid] < c) lo = mid + 1;
        else hi = mid - 1;
    }
    return -1;
}

/* Whether substituting unknown e through a row that also holds column p adds no entry: every
   row with column e other than `row` has column p. Uses the transposed pattern (t_ptr, t_rows). */
static int substitution_adds_nothing(const int *row_ptr, const int *cols, const int *t_ptr,
                                     const int *t_rows, int row, int e, int p)
{
    for (int t = t_ptr[e]; t < t_ptr[e + 1]; ++t)
        if (t_rows[t] != row && find_entry(row_ptr, cols, t_rows[t], p) < 0) return 0;
    return 1;
}

int rs_chain_lu_symbolic_permuted(int n, const int *row_ptr, const int *cols, const int *perm,
                                  rs_chain_lu **result)
{
    rs_chain_lu *lu;
    int         *unknown_of = NULL, *partner = NULL, *row_pos = NULL, *col_pos = NULL;
    int         *where = NULL, *kept_ptr = NULL, *kept_cols = NULL, *kept_perm = NULL;
    int         *t_ptr = NULL, *t_rows = NULL, *elim_of_col = NULL;
    int          status = 0, nnz_kept = 0, u = 0, k = 0, m = 0;
    const int    nnz = row_ptr ? row_ptr[n > 0 ? n : 0] : 0;

    *result = NULL;
    if (n < 1 || !row_ptr || !cols || row_ptr[0] != 0) return 1;
    for (int i = 0; i < n; ++i) {
        if (row_ptr[i + 1] < row_ptr[i]) return 1;
        for (int e = row_ptr[i]; e < row_ptr[i + 1]; ++e)
            if (cols[e] < 0 || cols[e] >= n || (e > row_ptr[i] && cols[e] <= cols[e - 1]))
                return 1;
    }
    lu = calloc(1, sizeof(*lu));
    if (!lu) return 2;
    lu->n       = n;
    unknown_of  = malloc((size_t)n * sizeof(int)); /* row i -> the unknown e it substitutes */
    partner     = malloc((size_t)n * sizeof(int));
    elim_of_col = malloc((size_t)n * sizeof(int));
    row_pos     = malloc((size_t)n * sizeof(int));
    col_pos     = malloc((size_t)n * sizeof(int));
    where       = malloc((size_t)n * sizeof(int));
    t_ptr       = calloc((size_t)n + 1, sizeof(int));
    t_rows      = malloc(((size_t)nnz + 1) * sizeof(int));
    if (!unknown_of || !partner || !elim_of_col || !row_pos || !col_pos || !where || !t_ptr ||
        !t_rows) {
        status = 2;
        goto done;
    }
    if (perm) {
        /* A permutation: every unknown once. */
        for (int c = 0; c < n; ++c) where[c] = 0;
        for (int p = 0; p < n; ++p) {
            if (perm[p] < 0 || perm[p] >= n || where[perm[p]]++) {
                status = 1;
                goto done;
            }
        }
    }
    /* The transposed pattern: the rows of each column. */
    for (int e = 0; e < nnz; ++e) ++t_ptr[cols[e] + 1];
    for (int c = 0; c < n; ++c) t_ptr[c + 1] += t_ptr[c];
    for (int r = 0; r < n; ++r)
        for (int e = row_ptr[r]; e < row_ptr[r + 1]; ++e) t_rows[t_ptr[cols[e]]++] = r;
    for (int c = n; c > 0; --c) t_ptr[c] = t_ptr[c - 1];
    t_ptr[0] = 0;
    /* Choose the substitutions: each unknown substituted once, partners kept. */
    for (int c = 0; c < n; ++c) elim_of_col[c] = -1;
    for (int i = 0; i < n; ++i) {
        unknown_of[i] = partner[i] = -1;
        if (row_ptr[i + 1] - row_ptr[i] != 2) continue;
        for (int side = 0; side < 2; ++side) {
            /* The diagonal unknown first, then the other one. */
            const int a = cols[row_ptr[i]], b = cols[row_ptr[i] + 1];
            const int e = (side == 0) == (a == i) ? a : b, p = e == a ? b : a;
            if (elim_of_col[e] >= 0 || elim_of_col[p] >= 0 ||
                !substitution_adds_nothing(row_ptr, cols, t_ptr, t_rows, i, e, p))
                continue;
            unknown_of[i]  = e;
            partner[i]     = p;
            elim_of_col[e] = i;
            break;
        }
    }
    /* A partner column that another row eliminated after all: undo that row's choice. */
    for (int i = 0; i < n; ++i)
        if (unknown_of[i] >= 0 && elim_of_col[partner[i]] >= 0) {
            elim_of_col[unknown_of[i]] = -1;
            unknown_of[i] = partner[i] = -1;
        }
    for (int i = 0; i < n; ++i) {
        row_pos[i] = unknown_of[i] >= 0 ? -1 : lu->n_kept++;
        if (unknown_of[i] >= 0) ++lu->n_elim;
    }
    for (int c = 0, kept = 0; c < n; ++c) col_pos[c] = elim_of_col[c] >= 0 ? -1 : kept++;
    for (int r = 0; r < n; ++r) {
        if (row_pos[r] < 0) continue;
        for (int e = row_ptr[r]; e < row_ptr[r + 1]; ++e) {
            if (col_pos[cols[e]] < 0) ++lu->n_updates;
            else ++nnz_kept;
        }
    }
#define ALLOCATE(pointer, count) ((pointer) = malloc(((size_t)(count) + 1) * sizeof(*(pointer))))
    if (!ALLOCATE(lu->kept_row, lu->n_kept) || !ALLOCATE(lu->kept_col, lu->n_kept) ||
        !ALLOCATE(lu->elim_row, lu->n_elim) || !ALLOCATE(lu->elim_col, lu->n_elim) ||
        !ALLOCATE(lu->elim_partner, lu->n_elim) || !ALLOCATE(lu->elim_pivot, lu->n_elim) ||
        !ALLOCATE(lu->elim_off, lu->n_elim) || !ALLOCATE(lu->inverse_pivot, lu->n_elim) ||
        !ALLOCATE(lu->ratio, lu->n_elim) || !ALLOCATE(lu->x_elim, lu->n_elim) ||
        !ALLOCATE(lu->entry_src, nnz_kept) || !ALLOCATE(lu->kept_values, nnz_kept) ||
        !ALLOCATE(lu->update_src, lu->n_updates) || !ALLOCATE(lu->update_dst, lu->n_updates) ||
        !ALLOCATE(lu->update_elim, lu->n_updates) || !ALLOCATE(lu->update_row, lu->n_updates) ||
        !ALLOCATE(lu->coefficient, lu->n_updates) || !ALLOCATE(lu->b_kept, lu->n_kept) ||
        !ALLOCATE(lu->x_kept, lu->n_kept) || !ALLOCATE(kept_ptr, lu->n_kept) ||
        !ALLOCATE(kept_cols, nnz_kept)) {
        status = 2;
        goto done;
    }
#undef ALLOCATE
    for (int i = 0; i < n; ++i) {
        if (row_pos[i] >= 0) lu->kept_row[row_pos[i]] = i;
        if (col_pos[i] >= 0) lu->kept_col[col_pos[i]] = i;
        if (unknown_of[i] < 0) continue;
        lu->elim_row[m]     = i;
        lu->elim_col[m]     = unknown_of[i];
        lu->elim_partner[m] = col_pos[partner[i]];
        lu->elim_pivot[m]   = find_entry(row_ptr, cols, i, unknown_of[i]);
        lu->elim_off[m]     = find_entry(row_ptr, cols, i, partner[i]);
        elim_of_col[unknown_of[i]] = m++; /* from now on: the index of its substitution */
    }
    /* The kept matrix (kept rows by kept columns, both in their order) and where the
       substitutions land in it. */
    for (int c = 0; c < n; ++c) where[c] = -1;
    kept_ptr[0] = 0;
    for (int q = 0; q < lu->n_kept; ++q) {
        const int r = lu->kept_row[q];
        for (int e = row_ptr[r]; e < row_ptr[r + 1]; ++e) {
            if (col_pos[cols[e]] < 0) continue;
            where[cols[e]]     = k;
            kept_cols[k]       = col_pos[cols[e]];
            lu->entry_src[k++] = e;
        }
        for (int e = row_ptr[r]; e < row_ptr[r + 1]; ++e) {
            if (col_pos[cols[e]] >= 0) continue;
            lu->update_src[u]  = e;
            lu->update_elim[u] = elim_of_col[cols[e]];
            lu->update_dst[u]  = where[partner[lu->elim_row[elim_of_col[cols[e]]]]];
            lu->update_row[u++] = q;
        }
        for (int e = row_ptr[r]; e < row_ptr[r + 1]; ++e) where[cols[e]] = -1;
        kept_ptr[q + 1] = k;
    }
    if (perm) {
        /* The chain order of the kept positions: that of their rows in perm. */
        if (!(kept_perm = malloc(((size_t)lu->n_kept + 1) * sizeof(int)))) {
            status = 2;
            goto done;
        }
        for (int p = 0, q = 0; p < n; ++p)
            if (row_pos[perm[p]] >= 0) kept_perm[q++] = row_pos[perm[p]];
    }
    status = core_symbolic(lu->n_kept, kept_ptr, kept_cols, kept_perm, &lu->core);
done:
    free(unknown_of);
    free(partner);
    free(elim_of_col);
    free(row_pos);
    free(col_pos);
    free(where);
    free(t_ptr);
    free(t_rows);
    free(kept_ptr);
    free(kept_cols);
    free(kept_perm);
    if (status) rs_chain_lu_free(lu);
    else *result = lu;
    return status;
}

int rs_chain_lu_symbolic(int n, const int *row_ptr, const int *cols, rs_chain_lu **lu)
{
    return rs_chain_lu_symbolic_permuted(n, row_ptr, cols, NULL, lu);
}

int rs_chain_lu_replan(rs_chain_lu *lu)
{
    return core_replan(lu->core);
}

void rs_chain_lu_get_info(const rs_chain_lu *lu, rs_chain_lu_info *info)
{
    core_get_info(lu->core, info);
    info->substituted = lu->n_elim;
}

int rs_chain_lu_numeric(rs_chain_lu *lu, const double *values, double pivot_tol)
{
    /* x_e = (b_i - a_ip x_p) / a_ie amplifies x_p by |a_ip / a_ie| (2/h for R_K's v): a
       substitution with a far larger ratio (a zero pivot, the endpoint equilibrium's R_K
       without q) is refused like a singular panel. */
    static const double largest_ratio = 1e8;

    for (int m = 0; m < lu->n_elim; ++m) {
        const double d = values[lu->elim_pivot[m]], o = values[lu->elim_off[m]];
        if (!(fabs(d) > 0.0) || !(fabs(o) <= largest_ratio * fabs(d))) return 1;
        lu->inverse_pivot[m] = 1.0 / d;
        lu->ratio[m]         = o / d;
    }
    for (int k = 0; k < lu->core->nnz; ++k) lu->kept_values[k] = values[lu->entry_src[k]];
    for (int u = 0; u < lu->n_updates; ++u) {
        const int m        = lu->update_elim[u];
        lu->coefficient[u] = values[lu->update_src[u]] * lu->inverse_pivot[m];
        lu->kept_values[lu->update_dst[u]] -= lu->coefficient[u] * values[lu->elim_off[m]];
    }
    return core_numeric(lu->core, lu->kept_values, pivot_tol);
}

void rs_chain_lu_solve(rs_chain_lu *lu, const double *b, double *x)
{
    for (int q = 0; q < lu->n_kept; ++q) lu->b_kept[q] = b[lu->kept_row[q]];
    for (int u = 0; u < lu->n_updates; ++u)
        lu->b_kept[lu->update_row[u]] -=
            lu->coefficient[u] * b[lu->elim_row[lu->update_elim[u]]];
    core_solve(lu->core, lu->b_kept, lu->x_kept);
    /* Everything is read from b before x is written (x may be b). */
    for (int m = 0; m < lu->n_elim; ++m)
        lu->x_elim[m] = lu->inverse_pivot[m] * b[lu->elim_row[m]] -
                        lu->ratio[m] * lu->x_kept[lu->elim_partner[m]];
    for (int q = 0; q < lu->n_kept; ++q) x[lu->kept_col[q]] = lu->x_kept[q];
    for (int m = 0; m < lu->n_elim; ++m) x[lu->elim_col[m]] = lu->x_elim[m];
}
