/* respond.c - the answers of texoptd's handlers: responses with the CORS headers, plain
 * texts, problem+json and the CORS preflight (see http_internal.h). Does not: route or
 * dispatch requests (http.c). */
#include "http_internal.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cors.h"
#include "problem.h"

/* The request's Origin, when --cors-origin lets it read the answer; NULL otherwise. */
static const char *cors_origin(const api_service *svc, struct MHD_Connection *c)
{
    return api_cors_allow(svc->config.cors_origin, MHD_lookup_connection_value(c, MHD_HEADER_KIND, "Origin"));
}

static void add_cors(const api_service *svc, struct MHD_Connection *c, struct MHD_Response *r)
{
    const char *allowed = svc->config.cors_origin;
    if (allowed[0] && strcmp(allowed, "*") != 0)
        MHD_add_response_header(r, "Vary", "Origin"); /* the answer depends on who asks */
    const char *origin = cors_origin(svc, c);
    if (!origin)
        return;
    MHD_add_response_header(r, "Access-Control-Allow-Origin", origin);
    MHD_add_response_header(r, "Access-Control-Expose-Headers",
                            "Location, Retry-After, Content-Disposition, Idempotent-Replayed");
}

enum MHD_Result http_send(request_ctx *rq, struct MHD_Connection *c, int status, struct MHD_Response *r)
{
    if (!r)
        return MHD_NO;
    add_cors(rq->svc, c, r);
    enum MHD_Result ok = MHD_queue_response(c, (unsigned)status, r);
    MHD_destroy_response(r);
    if (ok == MHD_YES)
        rq->status = status;
    return ok;
}

struct MHD_Response *http_response_owning(char *body, const char *content_type)
{
    if (!body)
        return NULL;
    struct MHD_Response *r = MHD_create_response_from_buffer(strlen(body), body, MHD_RESPMEM_MUST_FREE);
    if (!r) {
        free(body);
        return NULL;
    }
    MHD_add_response_header(r, "Content-Type", content_type);
    return r;
}

enum MHD_Result http_send_text(request_ctx *rq, struct MHD_Connection *c, int status, const char *content_type,
                               const char *body, size_t len)
{
    struct MHD_Response *r = MHD_create_response_from_buffer(len, (void *)body, MHD_RESPMEM_MUST_COPY);
    if (!r)
        return MHD_NO;
    if (content_type)
        MHD_add_response_header(r, "Content-Type", content_type);
    return http_send(rq, c, status, r);
}

enum MHD_Result http_send_problem(request_ctx *rq, struct MHD_Connection *c, int status, const char *slug,
                                  int retry_after, const char *fmt, ...)
{
    char detail[600];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(detail, sizeof detail, fmt, ap);
    va_end(ap);
    struct MHD_Response *r =
        http_response_owning(api_problem_json(status, slug, detail, rq->path), "application/problem+json");
    if (!r)
        return MHD_NO;
    if (retry_after > 0) {
        char seconds[16];
        snprintf(seconds, sizeof seconds, "%d", retry_after);
        MHD_add_response_header(r, "Retry-After", seconds);
    }
    if (status == 405)
        MHD_add_response_header(r, "Allow", api_route_allow(rq->match.route));
    if (status == 401)
        MHD_add_response_header(r, "WWW-Authenticate", "Bearer realm=\"texopt\"");
    return http_send(rq, c, status, r);
}

enum MHD_Result http_answer_options(request_ctx *rq, struct MHD_Connection *c)
{
    struct MHD_Response *r = MHD_create_response_from_buffer(0, (void *)"", MHD_RESPMEM_PERSISTENT);
    if (!r)
        return MHD_NO;
    MHD_add_response_header(r, "Allow", api_route_allow(rq->match.route));
    if (cors_origin(rq->svc, c)) {
        MHD_add_response_header(r, "Access-Control-Allow-Methods", api_route_allow(rq->match.route));
        MHD_add_response_header(r, "Access-Control-Allow-Headers",
                                "Authorization, Content-Type, Idempotency-Key, Last-Event-ID");
        MHD_add_response_header(r, "Access-Control-Max-Age", "600");
    }
    return http_send(rq, c, 204, r);
}
