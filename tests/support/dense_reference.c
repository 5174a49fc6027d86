/* The dense reference of the chain LU's tests (interface in dense_reference.h). */
#include "dense_reference.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static uint64_t lcg_state;

extern void dgesv_(const int *n, const int *nrhs, double *a, const int *lda, int *ipiv,
                   double *b, const int *ldb, int *info);
extern void dgecon_(const char *norm, const int *n, const double *a, const int *lda,
                    const double *anorm, double *rcond, double *work, int *iwork, int *info);

void lcg_seed(uint64_t seed)
{
    lcg_state = seed * 6364136223846793005ULL + 1442695040888963407ULL;
}

/* Uniform in [-1, 1), from the 53 high bits. */
double lcg_uniform(void)
{
    lcg_state = lcg_state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(lcg_state >> 11) * 0x1.0p-52 - 1.0;
}

/* Uniform integer in [lo, hi]. */
int lcg_int(int lo, int hi)
{
    lcg_state = lcg_state * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + (int)((lcg_state >> 33) % (uint64_t)(hi - lo + 1));
}

void rod_matrix_free(rod_matrix_t *m)
{
    free(m->a);
    free(m->stored);
    m->a      = NULL;
    m->stored = NULL;
}

double norm_inf_vector(int n, const double *x)
{
    double largest = 0.0;
    for (int i = 0; i < n; ++i)
        if (!(fabs(x[i]) <= largest)) largest = fabs(x[i]);
    return largest;
}

double norm_inf_matrix(const rod_matrix_t *m)
{
    double largest = 0.0;
    for (int i = 0; i < m->n; ++i) {
        double row = 0.0;
        for (int j = 0; j < m->n; ++j) row += fabs(m->a[i + (size_t)j * m->n]);
        if (row > largest) largest = row;
    }
    return largest;
}

/* ||b - A x|| / (||A|| ||x|| + ||b||) in the infinity norm: the normwise backward error. */
double backward_error(const rod_matrix_t *m, const double *x, const double *b)
{
    const int n = m->n;
    double   *r = malloc((size_t)n * sizeof(double)), error;

    for (int i = 0; i < n; ++i) r[i] = b[i];
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) r[i] -= m->a[i + (size_t)j * n] * x[j];
    error = norm_inf_vector(n, r) /
            (norm_inf_matrix(m) * norm_inf_vector(n, x) + norm_inf_vector(n, b));
    free(r);
    return error;
}

/* x = A^{-1} b by dgesv and the infinity-norm condition number estimate of dgecon. */
void dense_solve(const rod_matrix_t *m, const double *b, double *x, double *condition)
{
    const int n = m->n, one = 1;
    double   *lu = malloc((size_t)n * n * sizeof(double));
    double   *work = malloc(4 * (size_t)n * sizeof(double));
    int      *ipiv = malloc((size_t)n * sizeof(int)), *iwork = malloc((size_t)n * sizeof(int));
    int       info = 0;
    double    anorm = norm_inf_matrix(m), rcond = 0.0;

    memcpy(lu, m->a, (size_t)n * n * sizeof(double));
    memcpy(x, b, (size_t)n * sizeof(double));
    dgesv_(&n, &one, lu, &n, ipiv, x, &n, &info);
    if (info == 0) dgecon_("I", &n, lu, &n, &anorm, &rcond, work, iwork, &info);
    *condition = info == 0 && rcond > 0.0 ? 1.0 / rcond : HUGE_VAL;
    free(lu);
    free(work);
    free(ipiv);
    free(iwork);
}
