#include "rs_petsc_error_capture.h"

#include <stdio.h>

PetscErrorCode rs_capture_petsc_error(MPI_Comm comm, int line, const char *fun, const char *file,
                                      PetscErrorCode n, PetscErrorType p, const char *mess,
                                      void *ctx)
{
    RsErrorCapture *capture = (RsErrorCapture *)ctx;
    if (p == PETSC_ERROR_INITIAL && !capture->have) {
        snprintf(capture->text, sizeof(capture->text), "%s (PETSc error %d in %s)",
                 mess ? mess : "", (int)n, fun ? fun : "?");
        capture->have = 1;
    }
    /* PETSc still prints its trace, as everywhere else in rodsolve (src/core/error.f90). */
    return PetscTraceBackErrorHandler(comm, line, fun, file, n, p, mess, NULL);
}
