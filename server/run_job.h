/* run_job.h - one job through the engine: the service's only call into the pipeline.
 *
 * Does: build the paths (input, result.glb, stats.json in the job directory), the monitor
 * (progress into the store, stage durations into the metrics, the job's cancel flag), call
 * texopt_optimize_file (engine/job/pipeline.h), and end the job: succeeded, failed (with a
 * problem), canceled, or back to queued when the service is stopping. */
#ifndef TEXOPT_SERVER_RUN_JOB_H
#define TEXOPT_SERVER_RUN_JOB_H

#include <stdatomic.h>

#include "metrics.h"
#include "store.h"

void run_job(job_store *store, service_metrics *metrics, store_job *job, const job_record *record,
             const atomic_int *cancel, const atomic_int *stopping);

#endif
