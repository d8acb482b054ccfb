/* job_progress.c - a job's progress and cancellation (job_progress.h). */
#include "job_progress.h"

#include <string.h>
#include <time.h>

double job_now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void forward_progress(void *user, const texopt_progress *p)
{
    job_monitor *jm = user;
    texopt_progress q = *p;
    double sf = p->stage_fraction < 0 ? 0 : (p->stage_fraction > 1 ? 1 : p->stage_fraction);
    q.fraction = jm->from + (jm->to - jm->from) * sf;
    double elapsed = job_now_seconds() - jm->start;
    q.eta_seconds = q.fraction > 0.01 ? elapsed * (1 - q.fraction) / q.fraction : -1;
    texopt_monitor_report(jm->outer, &q);
}

void job_monitor_init(job_monitor *jm, const texopt_monitor *outer)
{
    memset(jm, 0, sizeof *jm);
    jm->outer = outer;
    jm->start = job_now_seconds();
    jm->inner.on_progress = forward_progress;
    jm->inner.user = jm;
    jm->inner.cancel = outer ? outer->cancel : NULL;
}

void job_stage(job_monitor *jm, const char *stage, double from, double to)
{
    jm->from = from;
    jm->to = to;
    texopt_progress p = {.stage = stage, .stage_fraction = 0, .eta_seconds = -1};
    forward_progress(jm, &p);
}

void job_stage_done(job_monitor *jm, const char *stage)
{
    texopt_progress p = {.stage = stage, .stage_fraction = 1, .eta_seconds = -1};
    forward_progress(jm, &p);
}

texopt_status job_check_cancel(const job_monitor *jm, char *err, size_t err_len)
{
    if (texopt_monitor_canceled(&jm->inner))
        return texopt_fail(err, err_len, TEXOPT_E_CANCELED, "job canceled");
    return TEXOPT_OK;
}
