/* run_job.c - runs one job with texopt_optimize_file (see run_job.h). The pipeline is
 * Sun et al. 2022; this file only wires its monitor to the store and the metrics. */
#include "run_job.h"

#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "job_report.h"
#include "log.h"
#include "problem.h"
#include "texopt.h"

typedef struct job_watch {
    job_store *store;
    service_metrics *metrics;
    store_job *job;
    char stage[16];
    double stage_started; /* monotonic seconds */
    double offset, scale; /* this part's share of the job's progress */
    int comparing;        /* the report's comparison: one stage, "compare" */
    double fraction;      /* of this part, last reported */
} job_watch;

static double monotonic_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* A stage ends when the next one reports or the job ends: that is its duration. */
static void close_stage(job_watch *w)
{
    if (w->stage[0])
        metrics_observe_stage(w->metrics, w->stage, monotonic_seconds() - w->stage_started);
    w->stage[0] = '\0';
}

/* The comparison runs whole jobs and evaluations inside it, each reporting its own 0..1
 * (an evaluation none at all): only the comparison's own steps move its progress. */
static double part_fraction(job_watch *w, const texopt_progress *p)
{
    int own = !w->comparing || (p->stage && strcmp(p->stage, "compare") == 0);
    if (own && p->fraction >= 0 && p->fraction > w->fraction)
        w->fraction = p->fraction > 1 ? 1 : p->fraction;
    return w->fraction;
}

static void on_progress(void *user, const texopt_progress *p)
{
    job_watch *w = user;
    const char *stage = w->comparing ? "compare" : p->stage ? p->stage : "";
    if (strncmp(w->stage, stage, sizeof w->stage - 1) != 0) {
        close_stage(w);
        snprintf(w->stage, sizeof w->stage, "%s", stage);
        w->stage_started = monotonic_seconds();
    }
    store_progress(w->store, w->job, stage, w->offset + w->scale * part_fraction(w, p), p->eta_seconds, p->mean_loss,
                   p->mean_area_scale);
}

void run_job(job_store *store, service_metrics *metrics, store_job *job, const job_record *record,
             const atomic_int *cancel, const atomic_int *stopping)
{
    /* The input is the job's; the outputs go where the store publishes them from. */
    char dir[PATH_MAX - 400], input[PATH_MAX], result[PATH_MAX], stats[PATH_MAX];
    store_job_dir(store, record->id, dir, sizeof dir);
    snprintf(input, sizeof input, "%s/%s", dir, record->input_rel);
    store_run_dir(store, job, dir, sizeof dir);
    snprintf(result, sizeof result, "%s/result.glb", dir);
    snprintf(stats, sizeof stats, "%s/stats.json", dir);

    /* With a report, the comparison (one input-layout run and two evaluations) is the last
     * fifth of the job's progress. */
    int evaluate = record->params.evaluate != 0;
    job_watch watch = {store, metrics, job, "", 0, 0, evaluate ? 0.8 : 1.0, 0, 0};
    texopt_monitor monitor = {on_progress, &watch, cancel};
    char err[512] = "";
    texopt_status status = texopt_optimize_file(input, result, stats, &record->params, &monitor, err, sizeof err);
    close_stage(&watch);
    int has_report = 0;
    if (status == TEXOPT_OK && evaluate) {
        watch.offset = 0.8;
        watch.scale = 0.2;
        watch.comparing = 1;
        watch.fraction = 0;
        char why[512] = "";
        texopt_status rs = job_write_report(input, dir, record->model_name, &record->params, &monitor, why, sizeof why);
        close_stage(&watch);
        if (rs == TEXOPT_OK) {
            has_report = 1;
        } else if (rs == TEXOPT_E_CANCELED) {
            status = rs;
        } else if (rs != TEXOPT_OK) {
            /* The optimised model is good; only the report is missing, and /report says so. */
            char quoted[600];
            log_event("level=warn event=report job=%s error=%s", record->id, log_quote(quoted, sizeof quoted, why));
        }
    }

    if (status == TEXOPT_OK) {
        store_finish(store, job, JOB_SUCCEEDED, NULL, has_report);
    } else if (status == TEXOPT_E_CANCELED && atomic_load(stopping)) {
        store_requeue(store, job);
    } else if (status == TEXOPT_E_CANCELED) {
        store_finish(store, job, JOB_CANCELED, NULL, 0);
    } else {
        job_problem problem;
        memset(&problem, 0, sizeof problem);
        /* An I/O failure inside a run is the server's disk, not a file the client forgot. */
        int io = status == TEXOPT_E_IO;
        problem.status = io ? 500 : api_status_from_engine(status);
        snprintf(problem.type, sizeof problem.type, "urn:texopt:problem:%s",
                 io ? "storage-error" : api_slug_from_engine(status));
        snprintf(problem.title, sizeof problem.title, "%s", texopt_strerror(status));
        snprintf(problem.detail, sizeof problem.detail, "%s", err[0] ? err : texopt_strerror(status));
        store_finish(store, job, JOB_FAILED, &problem, 0);
    }
}
