/* events.c - GET /v1/jobs/{id}/events: the job's progress as server-sent events.
 *
 * Each event carries the whole job resource (api/job_json.h) as its data, `event: state`
 * when the state differs from the last one this stream sent, else `event: progress`, and
 * `id:` the job's event sequence number. Events are coalesced: a stream sends the latest
 * state whenever it is behind, so a client that resumes with Last-Event-ID gets the current
 * state at once (not every step it missed). The stream ends after a finished state; asked
 * again with the finished state's id as Last-Event-ID, it answers 204 No Content.
 *
 * No busy loop: the content-reader callback waits on the store's condition variable with a
 * timeout (store_wait_event) and sends a comment line as keep-alive when it expires. The
 * wait holds only this connection's own thread (see the threading note in http.c). */
#define _DEFAULT_SOURCE
#include "http_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "job_json.h"

/* Seconds between keep-alive comments; proxies drop connections idle for much longer. */
#define KEEPALIVE_MS 15000

typedef struct event_stream {
    api_service *svc;
    job_store *store;
    char id[JOB_ID_LEN + 1];
    long long last_seq;
    job_state last_state; /* JOB_STATE_COUNT before the first event */
    int done;             /* the finished state was sent */
    char *pending;        /* formatted bytes not yet handed to libmicrohttpd */
    size_t pending_len, pending_off;
} event_stream;

static int format_event(event_stream *s, const job_record *job)
{
    char *data = api_job_text(job);
    if (!data)
        return -1;
    const char *name = job->state != s->last_state ? "state" : "progress";
    size_t cap = strlen(data) + 96;
    free(s->pending);
    s->pending = malloc(cap);
    if (!s->pending) {
        free(data);
        return -1;
    }
    int n = snprintf(s->pending, cap, "id: %lld\nevent: %s\ndata: %s\n\n", job->event_seq, name, data);
    free(data);
    s->pending_len = (size_t)n;
    s->pending_off = 0;
    s->last_seq = job->event_seq;
    s->last_state = job->state;
    s->done = job_state_finished(job->state);
    return 0;
}

static int set_pending_text(event_stream *s, const char *text)
{
    free(s->pending);
    s->pending = strdup(text);
    s->pending_len = s->pending ? strlen(text) : 0;
    s->pending_off = 0;
    return s->pending ? 0 : -1;
}

static ssize_t read_events(void *cls, uint64_t pos, char *buf, size_t max)
{
    (void)pos;
    event_stream *s = cls;
    if (s->pending_off == s->pending_len) {
        if (s->done)
            return MHD_CONTENT_READER_END_OF_STREAM;
        job_record job;
        int rc = store_wait_event(s->store, s->id, s->last_seq, KEEPALIVE_MS, &job);
        if (rc == 1) {
            if (format_event(s, &job) != 0)
                return MHD_CONTENT_READER_END_WITH_ERROR;
        } else if (rc == 0) {
            if (set_pending_text(s, ": keep-alive\n\n") != 0)
                return MHD_CONTENT_READER_END_WITH_ERROR;
        } else if (rc == STORE_NOT_FOUND) {
            s->done = 1;
            if (set_pending_text(s, "event: deleted\ndata: {}\n\n") != 0)
                return MHD_CONTENT_READER_END_WITH_ERROR;
        } else {
            return MHD_CONTENT_READER_END_OF_STREAM; /* shutting down */
        }
    }
    size_t n = s->pending_len - s->pending_off;
    if (n > max)
        n = max;
    memcpy(buf, s->pending + s->pending_off, n);
    s->pending_off += n;
    return (ssize_t)n;
}

static void free_stream(void *cls)
{
    event_stream *s = cls;
    atomic_fetch_sub(&s->svc->open_streams, 1);
    free(s->pending);
    free(s);
}

static long long last_event_id(struct MHD_Connection *c)
{
    const char *h = MHD_lookup_connection_value(c, MHD_HEADER_KIND, "Last-Event-ID");
    if (!h)
        h = MHD_lookup_connection_value(c, MHD_GET_ARGUMENT_KIND, "last_event_id");
    char *end = NULL;
    long long v = h ? strtoll(h, &end, 10) : 0;
    return h && end && *end == '\0' && v > 0 ? v : 0;
}

enum MHD_Result jobs_events(request_ctx *rq, struct MHD_Connection *c)
{
    job_record job;
    int rc = store_get(rq->svc->store, rq->match.id, &job);
    if (rc == STORE_IO)
        return http_store_unreachable(rq, c);
    if (rc != STORE_OK)
        return http_send_problem(rq, c, 404, "job-not-found", 0, "no job %s", rq->match.id);
    event_stream *s = calloc(1, sizeof *s);
    if (!s)
        return MHD_NO;
    s->svc = rq->svc;
    s->store = rq->svc->store;
    atomic_fetch_add(&rq->svc->open_streams, 1);
    memcpy(s->id, job.id, sizeof s->id);
    s->last_seq = last_event_id(c);
    s->last_state = JOB_STATE_COUNT;
    /* A finished job whose final event the client already has: 204 is what makes an
     * EventSource stop reconnecting (an empty 200 makes it retry every few seconds). */
    if (job_state_finished(job.state) && s->last_seq == job.event_seq) {
        free_stream(s);
        struct MHD_Response *none = MHD_create_response_from_buffer(0, (void *)"", MHD_RESPMEM_PERSISTENT);
        return http_send(rq, c, 204, none);
    }
    if (set_pending_text(s, "retry: 2000\n\n") != 0) /* reconnect after 2 s if cut */
        return free_stream(s), MHD_NO;
    struct MHD_Response *r = MHD_create_response_from_callback(MHD_SIZE_UNKNOWN, 4096, read_events, s, free_stream);
    if (!r) {
        free_stream(s);
        return MHD_NO;
    }
    MHD_add_response_header(r, "Content-Type", "text/event-stream");
    MHD_add_response_header(r, "Cache-Control", "no-store");
    MHD_add_response_header(r, "X-Accel-Buffering", "no");
    return http_send(rq, c, 200, r);
}
