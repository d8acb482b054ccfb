/* parallel.h - runs one function as several workers, the calling thread among them.
 *
 * Worker k of n is called with (char *)args + k * stride (stride 0: every worker gets args).
 * Worker 0 runs on the calling thread and the others on threads of their own; a worker
 * whose thread cannot start (no memory, a thread limit) runs on the calling thread after
 * worker 0, so the work is all done, only later. Returns when every worker has returned.
 * Does not: divide the work (workers take rows by their index or items from a shared
 * counter), bound the number of workers, or carry failures (workers record their own). */
#ifndef TEXOPT_PARALLEL_H
#define TEXOPT_PARALLEL_H

#include <stddef.h>

/* workers < 1 runs worker 0 alone. The worker's signature is pthread_create's. */
void texopt_parallel_run(void *(*worker)(void *), void *args, size_t stride, int workers);

#endif
