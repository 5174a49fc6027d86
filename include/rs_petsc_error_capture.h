/* The first message of a PETSc error, caught while a facade function (rod_stepper.c,
   modal_solver.c) runs, so the Fortran side reports it as rodsolve's error object (STYLE.md
   item 11). Push rs_capture_petsc_error with a zeroed RsErrorCapture as its context. */
#ifndef RS_PETSC_ERROR_CAPTURE_H
#define RS_PETSC_ERROR_CAPTURE_H

#include <petscsys.h>

typedef struct {
    char text[768];
    int  have;
} RsErrorCapture;

PetscErrorCode rs_capture_petsc_error(MPI_Comm comm, int line, const char *fun, const char *file,
                                      PetscErrorCode n, PetscErrorType p, const char *mess,
                                      void *ctx);

#endif
