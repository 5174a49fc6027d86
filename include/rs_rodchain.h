/* The chain LU (include/rs_chain_lu.h) as a PETSc solver package, so that a single rod's
   Jacobian is factored by it through the ordinary PCLU of the stepper's KSP and every other
   package stays selectable from the command line (DESIGN.md §3, "Structure first"):

       -pc_factor_mat_solver_type rodchain | mumps | petsc | ...

   For MATSEQAIJ, MAT_FACTOR_LU. The chain order is the matrix's own (the formulations number
   their unknowns along the rod). When a panel cannot be factored with pivoting inside it
   (a singular or cancelled Schur complement, e.g. a quasistatic rod whose first element
   floats), the factorization is tried from the other end of the chain, and if that fails too
   MUMPS factors that Jacobian; one line on standard error says so the first time. A matrix
   that MUMPS cannot factor either is reported as a factorization failure (PCFailedReason),
   never solved with a bad factor: the stepper then cuts the step.

   Options (prefix of the matrix):
     -mat_rodchain_pivot_tol <1e-13>  a pivot below this times the largest entry of its column
                                      in the panel counts as zero
     -mat_rodchain_check_tol <1e-10>  largest normwise backward error of the first solve of a
                                      factorization before MUMPS factors that Jacobian instead
     -mat_rodchain_replans <2>        plans of the panels tried (without the cuts that failed)
                                      after a plan with a singular panel, per direction
     -mat_rodchain_view               print the panels at the first factorization */
#ifndef RS_RODCHAIN_H
#define RS_RODCHAIN_H

#include <petscmat.h>

#define MATSOLVERRODCHAIN "rodchain"

/* Register the package with MatSolverTypeRegister (any number of times). */
PETSC_EXTERN PetscErrorCode rs_rodchain_register(void);

/* Of a factor matrix of the package: numeric factorizations done by the chain LU, and those
   MUMPS did instead. */
PETSC_EXTERN PetscErrorCode rs_rodchain_get_stats(Mat F, PetscInt *chain, PetscInt *fallback);

#endif
