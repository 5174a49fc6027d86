# Dependencies of rodsolve (DESIGN.md §2, §3): PETSc 3.18.x with MUMPS, MPI (C and Fortran),
# parallel HDF5 with its Fortran interface, METIS 5. Every failure says what is missing and how
# to install it (scripts/setup.sh installs all of it on Debian).
include(CheckCSourceCompiles)
find_package(PkgConfig REQUIRED)

set(_rs_install_hint "Run scripts/setup.sh, or: apt-get install petsc-dev slepc-dev libslepc-real3.18-dev libmumps-dev libmetis-dev libhdf5-openmpi-dev openmpi-bin libopenmpi-dev")

# --- MPI --------------------------------------------------------------------------------------
find_package(MPI REQUIRED COMPONENTS C Fortran)
if(NOT MPI_Fortran_HAVE_F90_MODULE)
    message(FATAL_ERROR "rodsolve: the MPI Fortran module (use mpi) was not found. ${_rs_install_hint}")
endif()
# mpiexec flags for tests and scripts: Open MPI refuses more ranks than cores without this.
set(RODSOLVE_MPIEXEC_FLAGS --oversubscribe CACHE STRING "Extra flags for mpiexec in tests")

# --- PETSc ------------------------------------------------------------------------------------
# Debian installs PETSc.pc under the PETSc prefix and links it into the multiarch pkgconfig dir.
pkg_check_modules(PETSC IMPORTED_TARGET PETSc)
if(NOT PETSC_FOUND)
    message(FATAL_ERROR "rodsolve: PETSc was not found by pkg-config (PETSc.pc). ${_rs_install_hint}")
endif()
# The custom time stepper uses PETSc's private TS header (DESIGN.md §3), whose layout changes
# between minor versions: PETSc is pinned to 3.18.x.
if(PETSC_VERSION VERSION_LESS 3.18 OR NOT PETSC_VERSION VERSION_LESS 3.19)
    message(FATAL_ERROR "rodsolve: PETSc ${PETSC_VERSION} found; rodsolve needs PETSc 3.18.x "
                        "(the rodmid time stepper builds against 3.18's TS implementation header).")
endif()
pkg_get_variable(PETSC_PREFIX PETSc prefix)
pkg_get_variable(PETSC_FCOMPILER PETSc fcompiler)
pkg_get_variable(PETSC_CCOMPILER PETSc ccompiler)
set(PETSC_INCLUDE_DIR ${PETSC_PREFIX}/include)
if(NOT EXISTS ${PETSC_INCLUDE_DIR}/petsc.mod)
    message(FATAL_ERROR "rodsolve: PETSc's Fortran modules (petsc.mod) are missing in ${PETSC_INCLUDE_DIR}.")
endif()
file(STRINGS ${PETSC_INCLUDE_DIR}/petscconf.h _petsc_mumps REGEX "define PETSC_HAVE_MUMPS 1")
if(NOT _petsc_mumps)
    message(FATAL_ERROR "rodsolve: PETSc ${PETSC_VERSION} at ${PETSC_PREFIX} was built without MUMPS; "
                        "rodsolve solves its saddle-point systems with MUMPS (DESIGN.md §3).")
endif()
set(CMAKE_REQUIRED_INCLUDES ${PETSC_INCLUDE_DIRS} ${MPI_C_INCLUDE_DIRS})
check_c_source_compiles("
#include <petscsys.h>
#include <stdint.h>
_Static_assert(sizeof(PetscReal) == sizeof(double), \"PetscReal must be double\");
_Static_assert(sizeof(PetscInt) == sizeof(int32_t), \"PetscInt must be 32-bit\");
#if defined(PETSC_USE_COMPLEX)
#error complex
#endif
int main(void) { return 0; }" RODSOLVE_PETSC_KINDS_MATCH)
unset(CMAKE_REQUIRED_INCLUDES)
if(NOT RODSOLVE_PETSC_KINDS_MATCH)
    message(FATAL_ERROR "rodsolve: PETSc must be a real, double-precision build with 32-bit "
                        "indices (PetscReal = c_double, PetscInt = c_int32_t; src/core/kinds.f90).")
endif()

# The compilers must agree with PETSc's: Fortran modules (petsc.mod, mpi.mod, hdf5.mod) are
# only readable by the gfortran major version that wrote them.
foreach(lang Fortran C)
    if(lang STREQUAL "Fortran")
        set(_petsc_cc ${PETSC_FCOMPILER})
    else()
        set(_petsc_cc ${PETSC_CCOMPILER})
    endif()
    execute_process(COMMAND ${_petsc_cc} -dumpfullversion OUTPUT_VARIABLE _petsc_cc_version
                    OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE _rc ERROR_QUIET)
    if(_rc EQUAL 0 AND NOT _petsc_cc_version STREQUAL CMAKE_${lang}_COMPILER_VERSION)
        message(FATAL_ERROR "rodsolve: the ${lang} compiler ${CMAKE_${lang}_COMPILER} "
                "(${CMAKE_${lang}_COMPILER_VERSION}) differs from PETSc's ${_petsc_cc} "
                "(${_petsc_cc_version}). Configure with -DCMAKE_${lang}_COMPILER=<PETSc's compiler>.")
    endif()
endforeach()

add_library(rodsolve::petsc INTERFACE IMPORTED)
target_link_libraries(rodsolve::petsc INTERFACE PkgConfig::PETSC MPI::MPI_C MPI::MPI_Fortran)
target_include_directories(rodsolve::petsc INTERFACE ${PETSC_INCLUDE_DIR})

# --- SLEPc ------------------------------------------------------------------------------------
# Modal analysis (docs/theory/modes.md) solves its eigenproblems with SLEPc, which must be the
# release of the PETSc it runs on (3.18.x, real): Debian's slepc-dev installs SLEPc.pc next to
# PETSc.pc. Only src/solver/ links it (one door per library, DESIGN.md §2).
pkg_check_modules(SLEPC IMPORTED_TARGET SLEPc)
if(NOT SLEPC_FOUND)
    message(FATAL_ERROR "rodsolve: SLEPc was not found by pkg-config (SLEPc.pc). ${_rs_install_hint}")
endif()
if(SLEPC_VERSION VERSION_LESS 3.18 OR NOT SLEPC_VERSION VERSION_LESS 3.19)
    message(FATAL_ERROR "rodsolve: SLEPc ${SLEPC_VERSION} found; rodsolve needs the SLEPc of its "
                        "PETSc, 3.18.x (apt-get install slepc-dev libslepc-real3.18-dev).")
endif()
add_library(rodsolve::slepc INTERFACE IMPORTED)
target_link_libraries(rodsolve::slepc INTERFACE PkgConfig::SLEPC rodsolve::petsc)

# MUMPS: its C header gives the version check of `rodsolve --version` a prototype.
find_path(MUMPS_INCLUDE_DIR dmumps_c.h PATH_SUFFIXES mumps)
find_library(MUMPS_LIBRARY NAMES dmumps dmumps-5.5)
if(NOT MUMPS_INCLUDE_DIR OR NOT MUMPS_LIBRARY)
    message(FATAL_ERROR "rodsolve: MUMPS (dmumps_c.h, libdmumps) not found. ${_rs_install_hint}")
endif()

# --- parallel HDF5 with Fortran ---------------------------------------------------------------
# Debian's libhdf5-openmpi-dev: the shared libraries PETSc itself links, never the static ones
# h5pfc shows (two HDF5 copies in one process do not share their global state).
find_path(HDF5_Fortran_MODULE_DIR hdf5.mod PATH_SUFFIXES hdf5/openmpi)
find_path(HDF5_C_INCLUDE_DIR H5pubconf.h PATH_SUFFIXES hdf5/openmpi)
find_library(HDF5_FORTRAN_LIBRARY NAMES hdf5_openmpi_fortran PATH_SUFFIXES hdf5/openmpi)
find_library(HDF5_C_LIBRARY NAMES hdf5_openmpi PATH_SUFFIXES hdf5/openmpi)
if(NOT HDF5_Fortran_MODULE_DIR OR NOT HDF5_C_INCLUDE_DIR OR NOT HDF5_FORTRAN_LIBRARY OR NOT HDF5_C_LIBRARY)
    message(FATAL_ERROR "rodsolve: parallel HDF5 with the Fortran interface (hdf5.mod, "
                        "libhdf5_openmpi_fortran) not found. ${_rs_install_hint}")
endif()
file(STRINGS ${HDF5_C_INCLUDE_DIR}/H5pubconf.h _h5_parallel REGEX "define H5_HAVE_PARALLEL 1")
if(NOT _h5_parallel)
    message(FATAL_ERROR "rodsolve: the HDF5 at ${HDF5_C_INCLUDE_DIR} is not a parallel build.")
endif()
add_library(rodsolve::hdf5 INTERFACE IMPORTED)
target_include_directories(rodsolve::hdf5 INTERFACE ${HDF5_Fortran_MODULE_DIR} ${HDF5_C_INCLUDE_DIR})
target_link_libraries(rodsolve::hdf5 INTERFACE ${HDF5_FORTRAN_LIBRARY} ${HDF5_C_LIBRARY} MPI::MPI_C)

# --- METIS ------------------------------------------------------------------------------------
find_path(METIS_INCLUDE_DIR metis.h)
find_library(METIS_LIBRARY metis)
if(NOT METIS_INCLUDE_DIR OR NOT METIS_LIBRARY)
    message(FATAL_ERROR "rodsolve: METIS (metis.h, libmetis) not found. ${_rs_install_hint}")
endif()
file(STRINGS ${METIS_INCLUDE_DIR}/metis.h _metis_idx REGEX "define IDXTYPEWIDTH 32")
file(STRINGS ${METIS_INCLUDE_DIR}/metis.h _metis_real REGEX "define REALTYPEWIDTH 32")
if(NOT _metis_idx OR NOT _metis_real)
    message(FATAL_ERROR "rodsolve: METIS must use 32-bit idx_t and real_t (src/parallel/metis.f90 binds them so).")
endif()
add_library(rodsolve::metis INTERFACE IMPORTED)
target_include_directories(rodsolve::metis INTERFACE ${METIS_INCLUDE_DIR})
target_link_libraries(rodsolve::metis INTERFACE ${METIS_LIBRARY})

message(STATUS "rodsolve: PETSc ${PETSC_VERSION} (${PETSC_PREFIX}), SLEPc ${SLEPC_VERSION}, MPI ${MPI_C_VERSION}, "
               "HDF5 ${HDF5_C_LIBRARY}, METIS ${METIS_LIBRARY}, MUMPS ${MUMPS_LIBRARY}")
