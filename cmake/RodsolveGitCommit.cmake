# Makes ${PROJECT_BINARY_DIR}/generated/rs_build_info.h with the git commit at build time (not
# configure time), rewritten only when it changes so that nothing rebuilds needlessly.
set(RODSOLVE_GENERATED_DIR ${PROJECT_BINARY_DIR}/generated)
file(MAKE_DIRECTORY ${RODSOLVE_GENERATED_DIR})
add_custom_target(rodsolve_git_commit
    COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${PROJECT_SOURCE_DIR}
            -DOUTPUT=${RODSOLVE_GENERATED_DIR}/rs_build_info.h
            -DVERSION=${PROJECT_VERSION}
            -P ${PROJECT_SOURCE_DIR}/cmake/WriteBuildInfo.cmake
    BYPRODUCTS ${RODSOLVE_GENERATED_DIR}/rs_build_info.h
    COMMENT "Recording the git commit")
