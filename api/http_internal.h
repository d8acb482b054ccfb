/* http_internal.h - what the request handlers (jobs.c, events.c, probes.c, web.c) share with
 * the libmicrohttpd glue in http.c and the answers in respond.c. Not a public interface. */
#ifndef TEXOPT_API_HTTP_INTERNAL_H
#define TEXOPT_API_HTTP_INTERNAL_H

#include <limits.h>
#include <microhttpd.h>
#include <stdint.h>

#include "routes.h"
#include "service.h"
#include "upload.h"

/* Per-request state, kept in libmicrohttpd's connection-context pointer and freed in the
 * completion callback. */
typedef struct request_ctx {
    api_service *svc;
    api_match match;
    char method[16];
    char path[256];
    size_t url_bytes; /* of the whole URL (path is cut to fit) */
    double started;   /* monotonic seconds */
    int status;       /* the status answered, 0 until then */
    /* POST /v1/jobs only: */
    api_upload *upload;
    char job_id[JOB_ID_LEN + 1];
    char job_dir[PATH_MAX - 512];
    int job_accepted;   /* keep the directory: it belongs to a job now */
    int key_known;      /* the Idempotency-Key names a job: replay it if the request matches */
    uint64_t discarded; /* body bytes thrown away (after a failure, or on GET/DELETE) */
} request_ctx;

/* Queues response with the status, adds the CORS headers, records the status and frees
 * the response. Returns libmicrohttpd's verdict. */
enum MHD_Result http_send(request_ctx *rq, struct MHD_Connection *c, int status, struct MHD_Response *r);

/* A response that owns body (a malloc'd string, freed with the response) with its
 * Content-Type; NULL when body is NULL or the response cannot be made (body is freed). */
struct MHD_Response *http_response_owning(char *body, const char *content_type);

/* A body from memory (copied). */
enum MHD_Result http_send_text(request_ctx *rq, struct MHD_Connection *c, int status, const char *content_type,
                               const char *body, size_t len);

/* An application/problem+json answer with the same status. retry_after > 0 adds Retry-After;
 * 405 adds Allow, 401 WWW-Authenticate. */
enum MHD_Result http_send_problem(request_ctx *rq, struct MHD_Connection *c, int status, const char *slug,
                                  int retry_after, const char *fmt, ...) __attribute__((format(printf, 6, 7)));

/* The answer to an OPTIONS request: Allow, and the CORS preflight's headers when the Origin
 * may read the answer. */
enum MHD_Result http_answer_options(request_ctx *rq, struct MHD_Connection *c);

/* Route handlers. */
enum MHD_Result jobs_post_headers(request_ctx *rq, struct MHD_Connection *c); /* first call */
enum MHD_Result jobs_post_body(request_ctx *rq, struct MHD_Connection *c, const char *data, size_t *size);
enum MHD_Result jobs_post_complete(request_ctx *rq, struct MHD_Connection *c);
enum MHD_Result jobs_list(request_ctx *rq, struct MHD_Connection *c);
enum MHD_Result jobs_get(request_ctx *rq, struct MHD_Connection *c);
enum MHD_Result jobs_delete(request_ctx *rq, struct MHD_Connection *c);
enum MHD_Result jobs_file(request_ctx *rq, struct MHD_Connection *c); /* result, stats, report */
enum MHD_Result jobs_events(request_ctx *rq, struct MHD_Connection *c);
enum MHD_Result probes_answer(request_ctx *rq,
                              struct MHD_Connection *c);               /* healthz, readyz, metrics, openapi, params */
enum MHD_Result web_answer(request_ctx *rq, struct MHD_Connection *c); /* the page and its files */

/* Jobs waiting for a worker: this node's queue, or the shared store's queued jobs (the
 * --queue-limit then bounds them over every node). */
int api_queue_depth(api_service *svc);

/* 503 + Retry-After: the store's database cannot be reached now (what is asked is not lost:
 * nothing was recorded). */
enum MHD_Result http_store_unreachable(request_ctx *rq, struct MHD_Connection *c);

/* Removes the directory of an upload that did not become a job. */
void jobs_post_abandon(request_ctx *rq);

#endif
