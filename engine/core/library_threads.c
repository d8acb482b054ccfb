/* library_threads.c - see library_threads.h. */
#include "library_threads.h"

#include <cblas.h>
#include <stdlib.h>

void texopt_limit_library_threads(void)
{
    if (!getenv("OPENBLAS_NUM_THREADS"))
        openblas_set_num_threads(1);
    setenv("LP_NUM_THREADS", "0", 0);
}
