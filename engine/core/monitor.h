/* monitor.h - progress reporting and cancellation, one struct passed through every stage.
 *
 * A stage reports its name, how far it is (0..1) and running statistics; the callback may
 * be called from any engine thread but never from two at once. A stage checks the cancel
 * flag between units of work (triangles, iterations, charts) and returns TEXOPT_E_CANCELED
 * when it is raised. A NULL monitor, callback or flag means nobody listens. */
#ifndef TEXOPT_MONITOR_H
#define TEXOPT_MONITOR_H

#include <stdatomic.h>

typedef struct texopt_progress {
    const char *stage;      /* "load", "stage1", "stage2", "pack", "bake", "evaluate", "save" */
    double stage_fraction;  /* 0..1 within the stage */
    double fraction;        /* 0..1 of the whole job */
    double mean_loss;       /* running mean of E over finished triangles (stage 1), else 0 */
    double mean_area_scale; /* running mean of lambda1 * lambda2 (stage 1), else 0 */
    double eta_seconds;     /* estimated seconds left for the whole job, < 0 when unknown */
} texopt_progress;

typedef void (*texopt_progress_fn)(void *user, const texopt_progress *progress);

typedef struct texopt_monitor {
    texopt_progress_fn on_progress;
    void *user;
    const atomic_int *cancel; /* non-zero: stop at the next checkpoint */
} texopt_monitor;

static inline int texopt_monitor_canceled(const texopt_monitor *monitor)
{
    return monitor && monitor->cancel && atomic_load(monitor->cancel) != 0;
}

static inline void texopt_monitor_report(const texopt_monitor *monitor, const texopt_progress *p)
{
    if (monitor && monitor->on_progress)
        monitor->on_progress(monitor->user, p);
}

#endif
