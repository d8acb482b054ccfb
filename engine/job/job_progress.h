/* job_progress.h - a job's progress and cancellation.
 *
 * Does: map each stage's own stage_fraction into a fixed share of the job (load, then per
 * domain, then save), add the ETA (the elapsed time extrapolated over that fraction), and
 * check the caller's cancel flag between stages. Does not: decide the shares of the stages
 * (job_methods.h holds each method's weights).
 * Progress: load, then per domain in proportion to its triangles (layout methods) or texels
 * (input), then save. Cancellation is checked between stages here and inside stages by the
 * stages themselves. */
#ifndef TEXOPT_JOB_PROGRESS_H
#define TEXOPT_JOB_PROGRESS_H

#include <stddef.h>

#include "monitor.h"
#include "status.h"

/* Wraps the caller's monitor: inner stages report their own stage_fraction, this maps it
 * into [from, to] of the job and adds the ETA. */
typedef struct job_monitor {
    const texopt_monitor *outer;
    texopt_monitor inner;
    double start;
    double from, to;
} job_monitor;

/* Seconds on the monotonic clock. */
double job_now_seconds(void);

void job_monitor_init(job_monitor *jm, const texopt_monitor *outer);

/* Sets the job range of the next stage and reports its start. */
void job_stage(job_monitor *jm, const char *stage, double from, double to);

/* Reports the end of the stage. */
void job_stage_done(job_monitor *jm, const char *stage);

/* TEXOPT_E_CANCELED once the caller raised the cancel flag. */
texopt_status job_check_cancel(const job_monitor *jm, char *err, size_t err_len);

#endif
