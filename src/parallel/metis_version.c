/* The METIS version of the header rodsolve was compiled against (METIS 5 has no run-time query). */
#include <metis.h>

void rs_metis_version(int *major, int *minor, int *subminor)
{
    *major = METIS_VER_MAJOR;
    *minor = METIS_VER_MINOR;
    *subminor = METIS_VER_SUBMINOR;
}
