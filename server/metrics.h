/* metrics.h - the service's counters, rendered as Prometheus text (format 0.0.4).
 *
 * Does: count HTTP requests by route template and status, upload bytes, and record how long
 * each engine stage took (a histogram per stage, seconds). Gauges that have an owner (jobs
 * by state, queue depth) are read from that owner when rendering, not copied here.
 * Does not: sample the process (CPU, memory). Thread-safe: one mutex. */
#ifndef TEXOPT_SERVER_METRICS_H
#define TEXOPT_SERVER_METRICS_H

#include <stddef.h>
#include <stdint.h>

#include "store.h"

typedef struct service_metrics service_metrics;

service_metrics *metrics_create(void);
void metrics_destroy(service_metrics *m); /* accepts NULL */

/* route is a template ("/v1/jobs/{id}"), a static string. */
void metrics_count_request(service_metrics *m, const char *route, int status);
void metrics_add_upload_bytes(service_metrics *m, uint64_t bytes);
/* stage is an engine stage name; unknown names are counted under "other". */
void metrics_observe_stage(service_metrics *m, const char *stage, double seconds);

/* Renders every metric (with the given gauges) into a new string (caller frees). */
char *metrics_render(service_metrics *m, const int job_counts[JOB_STATE_COUNT], int queue_depth, int queue_limit,
                     int workers_busy, int workers);

#endif
