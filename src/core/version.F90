!> The version and git commit of this build (generated/rs_build_info.h, written at build time
!> by cmake/WriteBuildInfo.cmake).
module rs_core_version
    implicit none
    private
#include "rs_build_info.h"

    !> rodsolve's version number.
    character(len=*), parameter, public :: rodsolve_version = RODSOLVE_VERSION
    !> The git commit the binary was built from ("-dirty" with local changes).
    character(len=*), parameter, public :: rodsolve_git_commit = RODSOLVE_GIT_COMMIT
end module rs_core_version
