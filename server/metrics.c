/* metrics.c - request counters, upload bytes and the stage-duration histograms, rendered in
 * the Prometheus text exposition format (see metrics.h). */
#define _DEFAULT_SOURCE
#include "metrics.h"

#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_REQUEST_SERIES 128

static const char *const stage_names[] = {"load", "stage1", "stage2", "pack", "bake", "evaluate", "save", "other"};
#define STAGE_COUNT (sizeof stage_names / sizeof stage_names[0])
/* Seconds; spans a small job's load (tens of ms) to a large stage 1 (tens of minutes). */
static const double bucket_bounds[] = {0.01, 0.05, 0.1, 0.5, 1, 5, 10, 30, 60, 300, 1800};
#define BUCKET_COUNT (sizeof bucket_bounds / sizeof bucket_bounds[0])

typedef struct request_series {
    const char *route;
    int status;
    uint64_t count;
} request_series;

typedef struct stage_histogram {
    uint64_t buckets[BUCKET_COUNT]; /* non-cumulative; summed when rendering */
    uint64_t count;
    double sum;
} stage_histogram;

struct service_metrics {
    pthread_mutex_t mu;
    request_series requests[MAX_REQUEST_SERIES];
    int request_series_count;
    uint64_t requests_dropped; /* series beyond MAX_REQUEST_SERIES (cannot happen with our routes) */
    uint64_t upload_bytes;
    stage_histogram stages[STAGE_COUNT];
};

service_metrics *metrics_create(void)
{
    service_metrics *m = calloc(1, sizeof *m);
    if (m)
        pthread_mutex_init(&m->mu, NULL);
    return m;
}

void metrics_destroy(service_metrics *m)
{
    if (!m)
        return;
    pthread_mutex_destroy(&m->mu);
    free(m);
}

void metrics_count_request(service_metrics *m, const char *route, int status)
{
    pthread_mutex_lock(&m->mu);
    int i = 0;
    while (i < m->request_series_count &&
           !(m->requests[i].status == status && strcmp(m->requests[i].route, route) == 0))
        i++;
    if (i == m->request_series_count && i < MAX_REQUEST_SERIES) {
        m->requests[i].route = route;
        m->requests[i].status = status;
        m->request_series_count++;
    }
    if (i < MAX_REQUEST_SERIES)
        m->requests[i].count++;
    else
        m->requests_dropped++;
    pthread_mutex_unlock(&m->mu);
}

void metrics_add_upload_bytes(service_metrics *m, uint64_t bytes)
{
    pthread_mutex_lock(&m->mu);
    m->upload_bytes += bytes;
    pthread_mutex_unlock(&m->mu);
}

void metrics_observe_stage(service_metrics *m, const char *stage, double seconds)
{
    size_t s = 0;
    while (s + 1 < STAGE_COUNT && strcmp(stage, stage_names[s]) != 0)
        s++;
    size_t b = 0;
    while (b < BUCKET_COUNT && seconds > bucket_bounds[b])
        b++;
    pthread_mutex_lock(&m->mu);
    if (b < BUCKET_COUNT)
        m->stages[s].buckets[b]++;
    m->stages[s].count++;
    m->stages[s].sum += seconds;
    pthread_mutex_unlock(&m->mu);
}

typedef struct text_buffer {
    char *data;
    size_t len, cap;
    int failed;
} text_buffer;

static void append(text_buffer *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void append(text_buffer *t, const char *fmt, ...)
{
    if (t->failed)
        return;
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int n = vsnprintf(t->data + t->len, t->cap - t->len, fmt, ap);
        va_end(ap);
        if (n < 0) {
            t->failed = 1;
            return;
        }
        if ((size_t)n < t->cap - t->len) {
            t->len += (size_t)n;
            return;
        }
        size_t cap = (t->cap + (size_t)n) * 2;
        char *data = realloc(t->data, cap);
        if (!data) {
            t->failed = 1;
            return;
        }
        t->data = data;
        t->cap = cap;
    }
}

char *metrics_render(service_metrics *m, const int job_counts[JOB_STATE_COUNT], int queue_depth, int queue_limit,
                     int workers_busy, int workers)
{
    text_buffer t = {malloc(4096), 0, 4096, 0};
    if (!t.data)
        return NULL;
    t.data[0] = '\0';
    append(&t, "# HELP texopt_jobs Jobs the service holds, by state.\n# TYPE texopt_jobs gauge\n");
    for (int s = 0; s < JOB_STATE_COUNT; s++)
        append(&t, "texopt_jobs{state=\"%s\"} %d\n", job_state_name((job_state)s), job_counts[s]);
    append(&t,
           "# HELP texopt_queue_depth Jobs waiting for a worker.\n# TYPE texopt_queue_depth gauge\n"
           "texopt_queue_depth %d\n",
           queue_depth);
    append(&t,
           "# HELP texopt_queue_limit Queued jobs accepted before answering 503.\n"
           "# TYPE texopt_queue_limit gauge\ntexopt_queue_limit %d\n",
           queue_limit);
    append(&t,
           "# HELP texopt_workers_busy Workers running a job.\n# TYPE texopt_workers_busy gauge\n"
           "texopt_workers_busy %d\n",
           workers_busy);
    append(&t, "# HELP texopt_workers Worker threads.\n# TYPE texopt_workers gauge\ntexopt_workers %d\n", workers);

    pthread_mutex_lock(&m->mu);
    append(&t,
           "# HELP texopt_upload_bytes_total Request body bytes received for job uploads.\n"
           "# TYPE texopt_upload_bytes_total counter\ntexopt_upload_bytes_total %llu\n",
           (unsigned long long)m->upload_bytes);
    append(&t, "# HELP texopt_http_requests_total HTTP requests answered, by route and status.\n"
               "# TYPE texopt_http_requests_total counter\n");
    for (int i = 0; i < m->request_series_count; i++)
        append(&t, "texopt_http_requests_total{route=\"%s\",status=\"%d\"} %llu\n", m->requests[i].route,
               m->requests[i].status, (unsigned long long)m->requests[i].count);
    append(&t, "# HELP texopt_stage_duration_seconds Time each engine stage of a job took.\n"
               "# TYPE texopt_stage_duration_seconds histogram\n");
    for (size_t s = 0; s < STAGE_COUNT; s++) {
        uint64_t cumulative = 0;
        for (size_t b = 0; b < BUCKET_COUNT; b++) {
            cumulative += m->stages[s].buckets[b];
            append(&t, "texopt_stage_duration_seconds_bucket{stage=\"%s\",le=\"%g\"} %llu\n", stage_names[s],
                   bucket_bounds[b], (unsigned long long)cumulative);
        }
        append(&t, "texopt_stage_duration_seconds_bucket{stage=\"%s\",le=\"+Inf\"} %llu\n", stage_names[s],
               (unsigned long long)m->stages[s].count);
        append(&t, "texopt_stage_duration_seconds_sum{stage=\"%s\"} %.6f\n", stage_names[s], m->stages[s].sum);
        append(&t, "texopt_stage_duration_seconds_count{stage=\"%s\"} %llu\n", stage_names[s],
               (unsigned long long)m->stages[s].count);
    }
    pthread_mutex_unlock(&m->mu);
    if (t.failed) {
        free(t.data);
        return NULL;
    }
    return t.data;
}
