/* Fortran preprocessor macros of rodsolve (STYLE.md items 11-12). Each stands on its own line.

   RS_SET_ERROR(err, routine, message)   set the allocatable type(error_t) err, with file and line
   RS_RETURN_IF_ERROR(err)               return when err is set (the caller propagates it)
   RS_CHECK_PETSC(ierr, err, routine, what)
                                         after a PETSc call: a non-zero ierr becomes an error_t
                                         naming the call, then return (PETSc's PetscCall only
                                         returns, it does not describe) */
#define RS_SET_ERROR(err, routine, message) call set_error(err, message, routine, __FILE__, __LINE__)
#define RS_RETURN_IF_ERROR(err) if (allocated(err)) return
#define RS_CHECK_PETSC(ierr, err, routine, what) if (ierr /= 0) then; call set_petsc_error(err, ierr, what, routine, __FILE__, __LINE__); return; end if
