/* parallel.c - see parallel.h. */
#include "parallel.h"

#include <pthread.h>
#include <stdlib.h>

static void *worker_arg(void *args, size_t stride, int k)
{
    return (char *)args + stride * (size_t)k;
}

void texopt_parallel_run(void *(*worker)(void *), void *args, size_t stride, int workers)
{
    pthread_t *threads = workers > 1 ? malloc(sizeof *threads * (size_t)(workers - 1)) : NULL;
    int started = 0; /* workers 1 .. started run on threads[0 .. started - 1] */
    while (threads && started < workers - 1 &&
           pthread_create(&threads[started], NULL, worker, worker_arg(args, stride, started + 1)) == 0)
        started++;
    worker(args);
    for (int k = started + 1; k < workers; k++)
        worker(worker_arg(args, stride, k));
    for (int k = 0; k < started; k++)
        pthread_join(threads[k], NULL);
    free(threads);
}
