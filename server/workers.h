/* workers.h - the threads that run jobs.
 *
 * DESIGN (after Redis bio.c). N worker threads, started once. Each takes a job id from the
 * queue (queue.h), marks the job running in the store, runs the whole engine pipeline on it
 * without holding any lock (run_job.c), and records the outcome. Workers own nothing but
 * the job they run; the store owns the jobs, the queue the waiting ids. HTTP threads never
 * wait for a worker: they queue and answer.
 *
 * Stopping (SIGTERM): workers_stop raises the cancel flag of every running job; the engine
 * stops at its next checkpoint and the job goes back to "queued" on disk (not "canceled"),
 * so it runs again from the start after the next start-up. Queued jobs stay queued.
 *
 * Memory: a worker takes a job only once its estimated memory fits in the budget beside the
 * running jobs' (memory_budget.h, config memory_budget); until then the job stays queued. */
#ifndef TEXOPT_SERVER_WORKERS_H
#define TEXOPT_SERVER_WORKERS_H

#include <stddef.h>

#include "config.h"
#include "metrics.h"
#include "queue.h"
#include "store.h"

typedef struct worker_pool worker_pool;

/* Starts config->workers threads. NULL with a message on failure. */
worker_pool *workers_start(job_store *store, job_queue *queue, service_metrics *metrics, const service_config *config,
                           char *err, size_t err_len);

/* Workers running a job now; worker threads. */
int workers_busy(const worker_pool *pool);
int workers_count(const worker_pool *pool);

/* Cancels running jobs back to queued, closes the queue and joins every thread. */
void workers_stop(worker_pool *pool);
void workers_destroy(worker_pool *pool); /* stops first if needed; accepts NULL */

#endif
