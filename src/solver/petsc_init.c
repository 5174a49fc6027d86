/* PETSc start-up and version queries for rodsolve.

   PETSc is initialized from C with the command-line arguments rodsolve did not consume itself
   (its own flags such as --help or --check-input never reach PETSc's option database, where
   they would print PETSc's help or be reported as unused options). PetscInitializeFortran then
   makes PETSc usable from the Fortran solver modules. */
#include <petscsys.h>
#include <dmumps_c.h>
#include <stdlib.h>
#include <string.h>

static int rs_argc = 0;
static char **rs_argv = NULL;
static char *rs_arg_storage = NULL;

/* `args` holds `count` NUL-terminated strings back to back, the program name first. */
int rs_petsc_initialize(int count, const char *args, int total_length)
{
    PetscErrorCode ierr;
    rs_arg_storage = malloc((size_t)total_length + 1);
    rs_argv = malloc(((size_t)count + 1) * sizeof(char *));
    if (!rs_arg_storage || !rs_argv) return 1;
    memcpy(rs_arg_storage, args, (size_t)total_length);
    rs_arg_storage[total_length] = '\0';
    char *p = rs_arg_storage;
    for (int i = 0; i < count; ++i) {
        rs_argv[i] = p;
        p += strlen(p) + 1;
    }
    rs_argv[count] = NULL;
    rs_argc = count;
    ierr = PetscInitialize(&rs_argc, &rs_argv, NULL, NULL);
    if (ierr) return (int)ierr;
    ierr = PetscInitializeFortran();
    return (int)ierr;
}

int rs_petsc_finalize(void)
{
    PetscErrorCode ierr = PetscFinalize();
    free(rs_argv);
    free(rs_arg_storage);
    rs_argv = NULL;
    rs_arg_storage = NULL;
    return (int)ierr;
}

int rs_petsc_initialized(void)
{
    PetscBool initialized = PETSC_FALSE;
    PetscInitialized(&initialized);
    return initialized ? 1 : 0;
}

/* PETSc's version line, e.g. "Petsc Release Version 3.18.5, Mar 03, 2023". */
void rs_petsc_version(char *buffer, int length)
{
    if (PetscGetVersion(buffer, (size_t)length)) buffer[0] = '\0';
}

/* The version of the MUMPS library actually linked, asked from an initialized instance. */
void rs_mumps_version(char *buffer, int length)
{
    DMUMPS_STRUC_C id;
    memset(&id, 0, sizeof(id));
    id.job = -1;
    id.par = 1;
    id.sym = 0;
    id.comm_fortran = (MUMPS_INT)MPI_Comm_c2f(MPI_COMM_SELF);
    dmumps_c(&id);
    /* Silence MUMPS (ICNTL(1..4)) before the terminating call, which would print a banner. */
    id.icntl[0] = -1;
    id.icntl[1] = -1;
    id.icntl[2] = -1;
    id.icntl[3] = 0;
    strncpy(buffer, id.version_number, (size_t)length - 1);
    buffer[length - 1] = '\0';
    id.job = -2;
    dmumps_c(&id);
}
