/* The chain LU: a direct solver for the Jacobian of one rod (DESIGN.md §3, "Structure first").

   A rod is a chain. Numbered along the rod (every formulation numbers its unknowns node by node
   with each element's interior unknowns beside its nodes), its Jacobian is block tridiagonal
   once the unknowns are cut into consecutive *panels*, and only a few unknowns of a panel (a
   node's) couple to the next one. The chain LU finds such panels from the nonzero pattern
   alone, so it knows nothing of formulations, then factors

       D_0 = A_00,   D_{k+1} = A_{k+1,k+1} - A_{k+1,k} D_k^{-1} A_{k,k+1}

   with LAPACK's dense LU with partial pivoting on each D_k and BLAS 3 for the coupling, which
   touches only the rows R_k and columns C_k of panel k+1 that are coupled to panel k. There is
   no analysis phase beyond the panels, no fill outside the dense blocks and no indirection in
   the loops, so a factorization runs at the speed of the dense kernels.

   Pivoting is partial and stays inside a panel: a panel whose Schur complement D_k is
   singular, or whose pivot falls below pivot_tol times the largest entry of its column
   (cancellation), cannot be factored this way although the matrix may be regular; numeric
   then returns the panel (1-based) and the caller uses a general sparse LU instead. This is
   the case of a constrained rod (ph_director with `constraint`): with both nodes of an
   element eliminated after it, the element's constraint rows are rank deficient (the mean
   strain over the element is fixed by its end nodes), so the first panel is singular from
   either end; factoring such chains needs pivots delayed across panels.

   Before the chain, rows with two entries (a_ie x_e + a_ip x_p = b_i) whose unknown x_e
   appears nowhere without x_p are substituted out (no entry is added): ph_director's kinematic
   rows, which take its velocities out of the panels (src/solver/chain_lu.c, "Substitution
   rows").

   Plain C on raw arrays (0-based CSR with sorted columns, doubles, column-major dense blocks);
   no PETSc, no allocation after symbolic. */
#ifndef RS_CHAIN_LU_H
#define RS_CHAIN_LU_H

#include <stddef.h>

typedef struct rs_chain_lu rs_chain_lu;

/* Cost of the panels, for choosing between the chain LU and a general sparse one. */
typedef struct {
    int    n_panels;
    int    largest_panel;   /* unknowns in the largest panel */
    int    widest_coupling; /* the largest |R_k| or |C_k| */
    double flops;           /* of one numeric factorization */
    double doubles;         /* stored values (the dense blocks) */
    int    substituted;     /* unknowns substituted before the chain (two-entry rows) */
    int    replans;         /* plans given up after a singular panel (rs_chain_lu_replan) */
} rs_chain_lu_info;

/* The panels of the n-by-n pattern (row_ptr: n + 1 entries, cols: row_ptr[n]) in its own
   ordering. Returns 0 and *lu, or non-zero (1: bad pattern, 2: out of memory) with *lu NULL. */
int rs_chain_lu_symbolic(int n, const int *row_ptr, const int *cols, rs_chain_lu **lu);

/* The same in the chain order perm (perm[p]: the unknown at chain position p; NULL: the
   pattern's own order), e.g. the pattern's order reversed, to factor from the other end. */
int rs_chain_lu_symbolic_permuted(int n, const int *row_ptr, const int *cols, const int *perm,
                                  rs_chain_lu **lu);

/* What symbolic found. */
void rs_chain_lu_get_info(const rs_chain_lu *lu, rs_chain_lu_info *info);

/* Factor the matrix with the pattern given to symbolic and the values `values` (in the order
   of the pattern). Returns 0, or k >= 1 when panel k - 1 has a zero or tiny pivot (the
   factorization is then unusable). */
int rs_chain_lu_numeric(rs_chain_lu *lu, const double *values, double pivot_tol);

/* Plan the panels again, without any cut of the plans tried so far, choosing among all
   positions: for a pattern whose first plan had a panel singular on its own. Returns 0; 1 if
   there is a single panel and 3 if no plan is left (the current plan stays); 2 out of memory
   (lu is then unusable). */
int rs_chain_lu_replan(rs_chain_lu *lu);

/* x = A^{-1} b with the last successful numeric factorization; x and b may be the same. */
void rs_chain_lu_solve(rs_chain_lu *lu, const double *b, double *x);

/* Free; NULL is fine. */
void rs_chain_lu_free(rs_chain_lu *lu);

#endif
