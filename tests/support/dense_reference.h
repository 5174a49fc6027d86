/* The dense reference of the chain LU's tests (tests/unit/solver/test_chain_lu.c and
   test_rodchain.c): a fixed-seed random generator, dense rod matrices, their norms, the normwise
   backward error of a solve and LAPACK's dense LU solve with its condition estimate. */
#ifndef RS_TEST_DENSE_REFERENCE_H
#define RS_TEST_DENSE_REFERENCE_H

#include <stdint.h>

/* Dense column-major values and the pattern (1: stored entry, possibly 0.0). */
typedef struct {
    int            n;
    double        *a;
    unsigned char *stored;
} rod_matrix_t;

/* A fixed-seed LCG (Knuth's MMIX constants), so every run is the same. */
void   lcg_seed(uint64_t seed);
double lcg_uniform(void);      /* uniform in [-1, 1) */
int    lcg_int(int lo, int hi); /* uniform in lo .. hi */

void   rod_matrix_free(rod_matrix_t *m);
double norm_inf_vector(int n, const double *x);
double norm_inf_matrix(const rod_matrix_t *m);
/* ||b - A x||_inf / (||A||_inf ||x||_inf + ||b||_inf) */
double backward_error(const rod_matrix_t *m, const double *x, const double *b);
/* x = A^{-1} b by LAPACK's dgesv, and the 1-norm condition estimate (dgecon). */
void   dense_solve(const rod_matrix_t *m, const double *b, double *x, double *condition);

#endif
