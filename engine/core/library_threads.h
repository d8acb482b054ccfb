/* library_threads.h - process-wide thread settings of the libraries the engine links.
 *
 * The engine runs its own worker threads. OpenBLAS's spinning threads on top of them cost
 * about 20x in wall time on two cores, and llvmpipe renders small viewports faster
 * unthreaded (shared/DEPENDENCIES.md). OpenBLAS reads OPENBLAS_NUM_THREADS when it is
 * loaded, before main(), so setting the variable from main is too late: this calls its
 * setter instead. An explicit OPENBLAS_NUM_THREADS or LP_NUM_THREADS in the environment
 * wins. Process-wide state: front ends (the CLI, texoptd) call it once at start, before any
 * engine work; the engine itself never does. */
#ifndef TEXOPT_LIBRARY_THREADS_H
#define TEXOPT_LIBRARY_THREADS_H

void texopt_limit_library_threads(void);

#endif
