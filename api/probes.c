/* probes.c - /healthz, /readyz, /metrics, /openapi.yaml and /v1/params (the engine's
 * defaults, which the page shows beside the ranges of openapi.yaml).
 * healthz: the process answers. readyz: it would accept a job now (not shutting down,
 * uploads and job states can be stored, queue not full) — what a load balancer should
 * route uploads by. */
#include "http_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "params_json.h"
#include "workers.h"

/* Seconds to wait before retrying while the store's database cannot be reached. */
#define DATABASE_RETRY_SECONDS 5

int api_queue_depth(api_service *svc)
{
    if (!store_shared(svc->store))
        return queue_depth(svc->queue);
    int counts[JOB_STATE_COUNT];
    store_counts(svc->store, counts);
    return counts[JOB_QUEUED];
}

enum MHD_Result http_store_unreachable(request_ctx *rq, struct MHD_Connection *c)
{
    return http_send_problem(rq, c, 503, "database-unavailable", DATABASE_RETRY_SECONDS,
                             "the job database cannot be reached now; retry shortly");
}

static enum MHD_Result answer_ready(request_ctx *rq, struct MHD_Connection *c)
{
    api_service *svc = rq->svc;
    if (atomic_load(&svc->draining))
        return http_send_problem(rq, c, 503, "shutting-down", 5, "the service is shutting down");
    if (store_unreachable(svc->store))
        return http_store_unreachable(rq, c);
    if (!store_can_store(svc->store, 0))
        return http_send_problem(rq, c, 503, "storage-full", 30,
                                 "uploads or job states cannot be stored now (the disk is full)");
    int depth = api_queue_depth(svc), limit = queue_limit(svc->queue);
    if (depth >= limit)
        return http_send_problem(rq, c, 503, "queue-full", 30, "the job queue is full (%d of %d)", depth, limit);
    char body[128];
    int n = snprintf(body, sizeof body, "{\"status\":\"ready\",\"queue_depth\":%d,\"queue_limit\":%d}", depth, limit);
    return http_send_text(rq, c, 200, "application/json", body, (size_t)n);
}

static enum MHD_Result answer_metrics(request_ctx *rq, struct MHD_Connection *c)
{
    api_service *svc = rq->svc;
    int counts[JOB_STATE_COUNT];
    store_counts(svc->store, counts);
    int busy = svc->workers ? workers_busy(svc->workers) : 0;
    int workers = svc->workers ? workers_count(svc->workers) : 0;
    int depth = store_shared(svc->store) ? counts[JOB_QUEUED] : queue_depth(svc->queue);
    char *text = metrics_render(svc->metrics, counts, depth, queue_limit(svc->queue), busy, workers);
    struct MHD_Response *r = http_response_owning(text, "text/plain; version=0.0.4; charset=utf-8");
    if (!r)
        return MHD_NO;
    return http_send(rq, c, 200, r);
}

/* {"defaults": {...}}: every parameter as a job without parameters would run. */
static enum MHD_Result answer_params(request_ctx *rq, struct MHD_Connection *c)
{
    texopt_params params;
    char err[256];
    if (api_params_from_json(NULL, &params, err, sizeof err) != TEXOPT_OK)
        return http_send_problem(rq, c, 500, "internal", 0, "%s", err);
    cJSON *body = cJSON_CreateObject();
    cJSON *defaults = api_params_to_json(&params);
    if (!body || !defaults || !cJSON_AddItemToObject(body, "defaults", defaults)) {
        cJSON_Delete(defaults);
        cJSON_Delete(body);
        return MHD_NO;
    }
    char *text = cJSON_PrintUnformatted(body);
    cJSON_Delete(body);
    return http_send(rq, c, 200, http_response_owning(text, "application/json"));
}

enum MHD_Result probes_answer(request_ctx *rq, struct MHD_Connection *c)
{
    switch (rq->match.route) {
    case ROUTE_HEALTHZ: return http_send_text(rq, c, 200, "application/json", "{\"status\":\"ok\"}", 15);
    case ROUTE_READYZ: return answer_ready(rq, c);
    case ROUTE_METRICS: return answer_metrics(rq, c);
    case ROUTE_OPENAPI:
        if (!rq->svc->openapi)
            return http_send_problem(rq, c, 404, "not-found", 0, "this build has no openapi.yaml");
        return http_send_text(rq, c, 200, "application/yaml", rq->svc->openapi, rq->svc->openapi_len);
    case ROUTE_PARAMS: return answer_params(rq, c);
    default: return http_send_problem(rq, c, 404, "not-found", 0, "no resource at %s", rq->path);
    }
}
