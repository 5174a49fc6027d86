# rodsolve_add_test: one test program, one CTest entry (DESIGN.md §8, STYLE.md item 18).
#
#   rodsolve_add_test(<name>
#       SOURCES <file>...            test program sources (tests/unit/<dir>/test_<module>.F90)
#       LIBRARIES <target>...        rodsolve libraries it needs (rs_core is always linked)
#       LABELS <label>...            unit | regression | mpi | input | slow | bench
#       [NRANKS <n>]                 run under mpirun -np <n> (0 or absent: run directly)
#       [ARGS <arg>...]              command-line arguments of the program
#       [TIMEOUT <seconds>])         default 300
#
# The program reports with rs_test_assert and exits non-zero on failure. Tests run in the
# build tree's tests/ directory; ${RODSOLVE_SOURCE_DIR} is in their environment.
function(rodsolve_add_test name)
    cmake_parse_arguments(T "" "NRANKS;TIMEOUT" "SOURCES;LIBRARIES;LABELS;ARGS" ${ARGN})
    if(NOT T_SOURCES)
        message(FATAL_ERROR "rodsolve_add_test(${name}): SOURCES is required")
    endif()
    if(NOT T_LABELS)
        message(FATAL_ERROR "rodsolve_add_test(${name}): LABELS is required")
    endif()
    if(NOT T_TIMEOUT)
        set(T_TIMEOUT 300)
    endif()
    add_executable(${name} ${T_SOURCES})
    target_link_libraries(${name} PRIVATE rs_test_support ${T_LIBRARIES})
    set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/tests/bin)
    if(T_NRANKS AND T_NRANKS GREATER 0)
        add_test(NAME ${name}
                 COMMAND ${MPIEXEC_EXECUTABLE} ${RODSOLVE_MPIEXEC_FLAGS} ${MPIEXEC_NUMPROC_FLAG} ${T_NRANKS}
                         $<TARGET_FILE:${name}> ${T_ARGS}
                 WORKING_DIRECTORY ${PROJECT_BINARY_DIR}/tests)
        set_tests_properties(${name} PROPERTIES PROCESSORS ${T_NRANKS})
    else()
        add_test(NAME ${name} COMMAND $<TARGET_FILE:${name}> ${T_ARGS}
                 WORKING_DIRECTORY ${PROJECT_BINARY_DIR}/tests)
    endif()
    set_tests_properties(${name} PROPERTIES
        LABELS "${T_LABELS}"
        TIMEOUT ${T_TIMEOUT}
        ENVIRONMENT "RODSOLVE_SOURCE_DIR=${PROJECT_SOURCE_DIR};OMPI_ALLOW_RUN_AS_ROOT=1;OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1;OMPI_MCA_rmaps_base_oversubscribe=1")
endfunction()
