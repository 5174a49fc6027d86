/* PETSc start-up and version queries for rodsolve.

   PETSc is initialized from C with the command-line arguments rodsolve did not consume itself
   (its own flags such as --help or --check-input never reach PETSc's option database, where
   they would print PETSc's help or be reported as unused options). PetscInitializeFortran then
   makes PETSc usable from the Fortran solver modules.

   The run's options are layered here (DESIGN.md §3 "Options": scene values first, then
   petsc_options, then the command line; interface in include/rs_rod_stepper.h). PETSc's
   database keeps one value per name and the last insertion wins, so re-inserting the command
   line after every scene insertion would be needed to keep it on top, and re-reading it is
   collective (PETSC_OPTIONS, .petscrc) while steppers are created rank by rank in sweeps.
   Instead each layer is kept as a list of names, and a layer sets only the names that no
   higher layer has: the command line set its values at PetscInitialize and is never touched
   again. */
#include <petscsys.h>
#include <dmumps_c.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "rs_rod_stepper.h"

static int rs_argc = 0;
static char **rs_argv = NULL;
static char *rs_arg_storage = NULL;

/* One layer of options: names without the leading '-', values (NULL for a flag). Plain
   malloc so that a layer outlives nothing it depends on. */
typedef struct {
    int n;
    char **names;
    char **values;
} RsOptionLayer;

static RsOptionLayer rs_command_line_layer = {0, NULL, NULL};
static RsOptionLayer rs_user_layer = {0, NULL, NULL};
static int rs_command_line_known = 0;

static void layer_free(RsOptionLayer *layer)
{
    for (int i = 0; i < layer->n; ++i) {
        free(layer->names[i]);
        free(layer->values[i]);
    }
    free(layer->names);
    free(layer->values);
    layer->n = 0;
    layer->names = NULL;
    layer->values = NULL;
}

static char *copy_text(const char *text)
{
    if (!text) return NULL;
    char *copy = malloc(strlen(text) + 1);
    if (copy) strcpy(copy, text);
    return copy;
}

/* Every option of a private database: nothing queries it, so PetscOptionsLeftGet lists all. */
static PetscErrorCode layer_from_database(PetscOptions db, RsOptionLayer *layer)
{
    PetscInt n = 0;
    char **names = NULL, **values = NULL;

    PetscFunctionBegin;
    PetscCall(PetscOptionsLeftGet(db, &n, &names, &values));
    layer->names = calloc((size_t)n + 1, sizeof(char *));
    layer->values = calloc((size_t)n + 1, sizeof(char *));
    PetscCheck(layer->names && layer->values, PETSC_COMM_SELF, PETSC_ERR_MEM, "option layer");
    for (PetscInt i = 0; i < n; ++i) {
        layer->names[i] = copy_text(names[i]);
        layer->values[i] = copy_text(values[i]);
        PetscCheck(layer->names[i] && (!values[i] || layer->values[i]), PETSC_COMM_SELF,
                   PETSC_ERR_MEM, "option layer");
        layer->n = (int)i + 1;
    }
    PetscCall(PetscOptionsLeftRestore(db, &n, &names, &values));
    PetscFunctionReturn(0);
}

/* Parse `text` as PETSc does for -options_string (quotes, -prefix_push, -options_file), but
   into a private database on PETSC_COMM_SELF. */
static PetscErrorCode layer_from_string(const char *text, RsOptionLayer *layer)
{
    PetscOptions db = NULL;
    PetscErrorCode ierr;

    PetscFunctionBegin;
    PetscCall(PetscOptionsCreate(&db));
    /* A bad string (e.g. -options_file of a missing file) is an input error to report, so
       the private database is freed on that path too. */
    ierr = PetscOptionsInsertString(db, text);
    if (!ierr) ierr = layer_from_database(db, layer);
    if (ierr) layer_free(layer);
    PetscCall(PetscOptionsDestroy(&db));
    PetscCall(ierr);
    PetscFunctionReturn(0);
}

/* Option names are case-insensitive in PETSc (PetscOptNameCmp). */
static int layer_has(const RsOptionLayer *layer, const char *name)
{
    for (int i = 0; i < layer->n; ++i)
        if (!strcasecmp(layer->names[i], name)) return 1;
    return 0;
}

static PetscErrorCode set_global_option(const char *name, const char *value, PetscBool clear)
{
    char key[512];

    PetscFunctionBegin;
    PetscCheck(strlen(name) + 2 <= sizeof(key), PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ,
               "option name too long: %s", name);
    snprintf(key, sizeof(key), "-%s", name);
    if (clear) PetscCall(PetscOptionsClearValue(NULL, key));
    else PetscCall(PetscOptionsSetValue(NULL, key, value));
    PetscFunctionReturn(0);
}

/* The command-line layer: the same sources PetscInitialize read (.petscrc files,
   PETSC_OPTIONS, argv), parsed again into a private database. Collective, like
   PetscInitialize. */
static PetscErrorCode capture_command_line(void)
{
    PetscOptions db = NULL;

    PetscFunctionBegin;
    layer_free(&rs_command_line_layer);
    PetscCall(PetscOptionsCreate(&db));
    PetscCall(PetscOptionsInsert(db, &rs_argc, &rs_argv, NULL));
    PetscCall(layer_from_database(db, &rs_command_line_layer));
    PetscCall(PetscOptionsDestroy(&db));
    rs_command_line_known = 1;
    PetscFunctionReturn(0);
}

static PetscErrorCode apply_options(const char *scene_options, const char *user_options)
{
    RsOptionLayer layer = {0, NULL, NULL};

    PetscFunctionBegin;
    PetscCheck(rs_command_line_known, PETSC_COMM_SELF, PETSC_ERR_ORDER,
               "rs_petsc_apply_options needs PETSc started by rs_petsc_initialize");
    if (user_options) {
        PetscCall(layer_from_string(user_options, &layer));
        for (int i = 0; i < rs_user_layer.n; ++i) {
            const char *name = rs_user_layer.names[i];
            if (!layer_has(&layer, name) && !layer_has(&rs_command_line_layer, name))
                PetscCall(set_global_option(name, NULL, PETSC_TRUE));
        }
        layer_free(&rs_user_layer);
        rs_user_layer = layer;
        for (int i = 0; i < rs_user_layer.n; ++i) {
            const char *name = rs_user_layer.names[i];
            if (!layer_has(&rs_command_line_layer, name))
                PetscCall(set_global_option(name, rs_user_layer.values[i], PETSC_FALSE));
        }
    }
    if (scene_options) {
        RsOptionLayer scene = {0, NULL, NULL};
        PetscCall(layer_from_string(scene_options, &scene));
        for (int i = 0; i < scene.n; ++i) {
            const char *name = scene.names[i];
            if (!layer_has(&rs_user_layer, name) && !layer_has(&rs_command_line_layer, name))
                PetscCall(set_global_option(name, scene.values[i], PETSC_FALSE));
        }
        layer_free(&scene);
    }
    PetscFunctionReturn(0);
}

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
    if (ierr) return (int)ierr;
    ierr = capture_command_line();
    return (int)ierr;
}

/* src/solver/modal_solver.c: SLEPc, when a modal analysis started it, ends before PETSc. */
int rs_slepc_finalize(void);

int rs_petsc_finalize(void)
{
    rs_slepc_finalize();
    layer_free(&rs_command_line_layer);
    layer_free(&rs_user_layer);
    rs_command_line_known = 0;
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

int rs_petsc_apply_options(const char *scene_options, const char *user_options, char *errmsg,
                           int errlen)
{
    PetscErrorCode ierr = apply_options(scene_options, user_options);
    if (ierr && errmsg && errlen > 0) {
        const char *text = NULL;
        PetscErrorMessage(ierr, &text, NULL);
        snprintf(errmsg, (size_t)errlen,
                 "the PETSc options could not be applied (PETSc error %d: %s; message above); "
                 "scene options \"%s\", petsc_options \"%s\"",
                 (int)ierr, text ? text : "unknown", scene_options ? scene_options : "",
                 user_options ? user_options : "");
    }
    return (int)ierr;
}

int rs_petsc_options_text(char *buffer, int length)
{
    char *all = NULL;
    if (PetscOptionsGetAll(NULL, &all)) return -1;
    size_t n = strlen(all);
    if (buffer && length > 0) {
        size_t copied = n < (size_t)length - 1 ? n : (size_t)length - 1;
        memcpy(buffer, all, copied);
        buffer[copied] = '\0';
    }
    PetscFree(all);
    return (int)n;
}

/* The options the user gave (command line or a scene's petsc_options) that nothing has read
   so far, as "-name (where)" separated by "; ", the count returned (-1 if PETSc failed). A
   misspelled option is one of them (PETSc's -options_left, for the user's options only:
   rodsolve's own defaults are set whether a run reads them or not). */
int rs_petsc_unused_options(char *buffer, int length)
{
    PetscInt n = 0, count = 0;
    char   **names = NULL, **values = NULL;
    size_t   used = 0;
    if (buffer && length > 0) buffer[0] = '\0';
    if (PetscOptionsLeftGet(NULL, &n, &names, &values)) return -1;
    for (PetscInt i = 0; i < n; ++i) {
        const char *name = names[i][0] == '-' ? names[i] + 1 : names[i];
        const char *where = layer_has(&rs_command_line_layer, name) ? "command line"
                            : layer_has(&rs_user_layer, name)       ? "petsc_options"
                                                                    : NULL;
        if (!where) continue;
        ++count;
        if (buffer && length > 0 && used < (size_t)length) {
            int written = snprintf(buffer + used, (size_t)length - used, "%s-%s (%s)",
                                   count > 1 ? "; " : "", name, where);
            if (written > 0) used += (size_t)written;
        }
    }
    PetscOptionsLeftRestore(NULL, &n, &names, &values);
    return (int)count;
}

int rs_petsc_log_begin(void)
{
    return (int)PetscLogDefaultBegin();
}

int rs_petsc_event_count(const char *name, int *count)
{
    PetscBool active = PETSC_FALSE;
    PetscLogEvent event = -1;
    PetscEventPerfInfo info;
    PetscErrorCode ierr;

    *count = -1;
    ierr = PetscLogIsActive(&active);
    if (ierr) return (int)ierr;
    if (!active) return 1;
    ierr = PetscLogEventGetId(name, &event);
    if (ierr) return (int)ierr;
    *count = 0;
    if (event < 0) return 0;
    ierr = PetscLogEventGetPerfInfo(PETSC_DETERMINE, event, &info);
    if (ierr) return (int)ierr;
    *count = info.count;
    return 0;
}
