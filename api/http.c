/* http.c - the libmicrohttpd daemon and request dispatch of texoptd.
 *
 * Threading model: MHD_USE_THREAD_PER_CONNECTION (with its internal polling thread for
 * accepting). Chosen because two kinds of request legitimately wait: an event stream
 * waits on the store's condition variable (with a timeout, no busy loop) inside its
 * content-reader callback, and an upload writes its body to disk and loads the model once
 * to validate it. With a thread per connection such a wait holds only its own connection;
 * polling clients are never behind it. (libmicrohttpd cannot combine thread-per-connection
 * with epoll or a thread pool; the cost is one thread per open connection, bounded by
 * --max-connections.) The engine itself never runs here: jobs go to the queue.
 *
 * Order of checks, after systemd-journal-remote: route, method (405 + Allow), auth (401),
 * then for uploads Content-Type (415), Content-Length (413) and queue room (503) before
 * a byte of the body is read. */
#define _DEFAULT_SOURCE
#include "http_internal.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "cors.h"
#include "head_watch.h"
#include "log.h"
#include "problem.h"
#include "texopt.h"

/* A body on a request that takes none is read and dropped up to this size, then cut. */
#define MAX_IGNORED_BODY_BYTES (1u << 20)
/* Request heads up to HEAD_MEMORY_BYTES reach texoptd, which refuses a URL or head past
 * these limits as problem+json (414, 431); libmicrohttpd refuses larger heads itself, with
 * its own short HTML answer, as it does a malformed Content-Length (before any callback). */
#define MAX_URL_BYTES (16u << 10)
#define MAX_HEAD_BYTES (64u << 10)
#define HEAD_MEMORY_BYTES ((size_t)512 << 10)

static double monotonic_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* Compares without an early exit, so response time does not reveal a token prefix. */
static int same_secret(const char *a, const char *b)
{
    size_t n = strlen(a), m = strlen(b);
    unsigned char diff = (unsigned char)(n != m);
    for (size_t i = 0; i < n; i++)
        diff |= (unsigned char)(a[i] ^ b[i % (m ? m : 1)]);
    return diff == 0;
}

static int authorized(const api_service *svc, struct MHD_Connection *c)
{
    if (!svc->config.api_token[0])
        return 1;
    const char *h = MHD_lookup_connection_value(c, MHD_HEADER_KIND, "Authorization");
    if (!h || strncasecmp(h, "Bearer ", 7) != 0)
        return 0;
    return same_secret(h + 7, svc->config.api_token);
}

static enum MHD_Result dispatch(request_ctx *rq, struct MHD_Connection *c)
{
    switch (rq->match.route) {
    case ROUTE_JOBS: return jobs_list(rq, c);
    case ROUTE_JOB: return strcmp(rq->method, "DELETE") == 0 ? jobs_delete(rq, c) : jobs_get(rq, c);
    case ROUTE_JOB_EVENTS: return jobs_events(rq, c);
    case ROUTE_JOB_RESULT:
    case ROUTE_JOB_STATS:
    case ROUTE_JOB_REPORT: return jobs_file(rq, c);
    case ROUTE_PAGE:
    case ROUTE_ASSET: return web_answer(rq, c);
    default: return probes_answer(rq, c);
    }
}

static enum MHD_Result add_header_bytes(void *cls, enum MHD_ValueKind kind, const char *key, const char *value)
{
    (void)kind;
    *(size_t *)cls += strlen(key) + (value ? strlen(value) : 0) + 4; /* ": " and CRLF */
    return MHD_YES;
}

static size_t head_bytes(struct MHD_Connection *c)
{
    size_t n = 0;
    MHD_get_connection_values(c, MHD_HEADER_KIND, add_header_bytes, &n);
    return n;
}

/* The first call for a request: everything that can be decided from the headers. */
static enum MHD_Result first_call(request_ctx *rq, struct MHD_Connection *c)
{
    if (rq->url_bytes > MAX_URL_BYTES)
        return http_send_problem(rq, c, 414, "uri-too-long", 0, "the URL has %zu bytes, more than %u", rq->url_bytes,
                                 MAX_URL_BYTES);
    size_t head = head_bytes(c);
    if (head > MAX_HEAD_BYTES)
        return http_send_problem(rq, c, 431, "headers-too-large", 0, "the headers have %zu bytes, more than %u", head,
                                 MAX_HEAD_BYTES);
    if (rq->match.route == ROUTE_NOT_FOUND)
        return http_send_problem(rq, c, 404, "not-found", 0, "no resource at %s", rq->path);
    if (strcmp(rq->method, "OPTIONS") == 0)
        return http_answer_options(rq, c);
    if (!api_route_allows(rq->match.route, rq->method))
        return http_send_problem(rq, c, 405, "method-not-allowed", 0, "%s is not allowed on %s (allowed: %s)",
                                 rq->method, api_route_template(rq->match.route), api_route_allow(rq->match.route));
    if (!api_route_is_public(rq->match.route) && !authorized(rq->svc, c))
        return http_send_problem(rq, c, 401, "unauthorized", 0, "a valid 'Authorization: Bearer <token>' is required");
    if (strcmp(rq->method, "POST") == 0)
        return jobs_post_headers(rq, c);
    return dispatch(rq, c);
}

static head_entry *head_of(struct MHD_Connection *c)
{
    const union MHD_ConnectionInfo *info = MHD_get_connection_info(c, MHD_CONNECTION_INFO_SOCKET_CONTEXT);
    return info ? info->socket_context : NULL;
}

/* Every connection is watched while it sends a request head (head_watch.h). */
static void on_connection(void *cls, struct MHD_Connection *c, void **socket_context,
                          enum MHD_ConnectionNotificationCode code)
{
    api_service *svc = cls;
    if (code == MHD_CONNECTION_NOTIFY_STARTED) {
        const union MHD_ConnectionInfo *fd = MHD_get_connection_info(c, MHD_CONNECTION_INFO_CONNECTION_FD);
        const union MHD_ConnectionInfo *addr = MHD_get_connection_info(c, MHD_CONNECTION_INFO_CLIENT_ADDRESS);
        *socket_context =
            fd ? head_watch_open(svc->heads, fd->connect_fd, addr ? addr->client_addr : NULL, monotonic_seconds())
               : NULL;
        return;
    }
    head_watch_close(svc->heads, *socket_context);
    *socket_context = NULL;
}

static enum MHD_Result on_request(void *cls, struct MHD_Connection *c, const char *url, const char *method,
                                  const char *version, const char *upload_data, size_t *upload_data_size,
                                  void **con_cls)
{
    (void)version;
    request_ctx *rq = *con_cls;
    if (!rq) {
        head_watch_done(((api_service *)cls)->heads, head_of(c));
        rq = calloc(1, sizeof *rq);
        if (!rq)
            return MHD_NO;
        *con_cls = rq;
        rq->svc = cls;
        rq->started = monotonic_seconds();
        snprintf(rq->method, sizeof rq->method, "%s", method);
        snprintf(rq->path, sizeof rq->path, "%s", url);
        rq->url_bytes = strlen(url);
        rq->match = api_route_match(url);
        /* Only an upload is answered from the headers alone (its refusals must come before
         * the body). Other requests are answered on the next call, once libmicrohttpd has
         * the whole request: answering earlier makes it close the connection, and pollers
         * lose keep-alive. */
        if (strcmp(method, "POST") == 0)
            return first_call(rq, c);
        return MHD_YES;
    }
    if (strcmp(rq->method, "POST") != 0) {
        /* A body on GET/DELETE/OPTIONS (axios sends `{}` with DELETE) means nothing here: it
         * is read and dropped, and the request answered once it is complete (an answer
         * queued while body bytes are pending makes libmicrohttpd drop the connection). */
        if (*upload_data_size > 0) {
            rq->discarded += *upload_data_size;
            *upload_data_size = 0;
            return rq->discarded > MAX_IGNORED_BODY_BYTES ? MHD_NO : MHD_YES;
        }
        return rq->status ? MHD_YES : first_call(rq, c);
    }
    if (rq->status) {
        /* Answered already (an early refusal): the rest of the body is not wanted. */
        *upload_data_size = 0;
        return MHD_YES;
    }
    if (*upload_data_size > 0)
        return jobs_post_body(rq, c, upload_data, upload_data_size);
    return jobs_post_complete(rq, c);
}

static void on_completed(void *cls, struct MHD_Connection *c, void **con_cls, enum MHD_RequestTerminationCode toe)
{
    api_service *svc = cls;
    if (toe == MHD_REQUEST_TERMINATED_COMPLETED_OK)
        head_watch_again(svc->heads, head_of(c), monotonic_seconds()); /* keep-alive: the next head */
    request_ctx *rq = *con_cls;
    if (!rq)
        return;
    const char *route = api_route_template(rq->match.route);
    metrics_count_request(svc->metrics, route, rq->status);
    if (rq->upload || rq->job_id[0])
        metrics_add_upload_bytes(svc->metrics, rq->upload ? api_upload_bytes(rq->upload) : 0);
    char path[300], job[48] = "";
    if (rq->job_accepted)
        snprintf(job, sizeof job, " job=%s", rq->job_id);
    log_event("level=info event=request method=%s path=%s route=%s status=%d duration_ms=%.3f%s%s", rq->method,
              log_quote(path, sizeof path, rq->path), route, rq->status, (monotonic_seconds() - rq->started) * 1e3, job,
              toe == MHD_REQUEST_TERMINATED_COMPLETED_OK ? "" : " aborted=true");
    jobs_post_abandon(rq);
    api_upload_destroy(rq->upload);
    free(rq);
    *con_cls = NULL;
}

/* libmicrohttpd logs every connection a client drops mid-request: under a slowloris load
 * that is thousands of lines a second, so at most MHD_LOG_PER_SECOND are written and the
 * rest counted in the next line written. */
#define MHD_LOG_PER_SECOND 20

static void on_mhd_log(void *cls, const char *fmt, va_list ap)
{
    api_log_limit *limit = cls;
    long now = (long)monotonic_seconds();
    pthread_mutex_lock(&limit->mu);
    if (now != limit->second) {
        limit->second = now;
        limit->written = 0;
    }
    int write = limit->written < MHD_LOG_PER_SECOND;
    long long dropped = write ? limit->dropped : 0;
    if (write) {
        limit->written++;
        limit->dropped = 0;
    } else {
        limit->dropped++;
    }
    pthread_mutex_unlock(&limit->mu);
    if (!write)
        return;
    char text[400], quoted[420];
    vsnprintf(text, sizeof text, fmt, ap);
    log_event("level=warn event=http message=%s dropped_before=%lld", log_quote(quoted, sizeof quoted, text), dropped);
}

struct MHD_Daemon *api_http_start(api_service *svc, int *port_out, char *err, size_t err_len)
{
    struct sockaddr_storage addr;
    memset(&addr, 0, sizeof addr);
    unsigned int flags =
        MHD_USE_THREAD_PER_CONNECTION | MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_ITC | MHD_USE_ERROR_LOG;
    struct sockaddr_in *v4 = (struct sockaddr_in *)&addr;
    struct sockaddr_in6 *v6 = (struct sockaddr_in6 *)&addr;
    if (inet_pton(AF_INET, svc->config.bind, &v4->sin_addr) == 1) {
        v4->sin_family = AF_INET;
        v4->sin_port = htons((uint16_t)svc->config.port);
    } else if (inet_pton(AF_INET6, svc->config.bind, &v6->sin6_addr) == 1) {
        v6->sin6_family = AF_INET6;
        v6->sin6_port = htons((uint16_t)svc->config.port);
        flags |= MHD_USE_IPv6;
    } else {
        texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "bind: '%s' is not an IPv4 or IPv6 address",
                    svc->config.bind);
        return NULL;
    }
    const service_config *cfg = &svc->config;
    /* Trickling heads may hold half the connections and a quarter of an address's, so a
     * request that sends its head at once finds room, from that address too (head_watch.h). */
    svc->heads = head_watch_create(cfg->header_timeout_seconds, cfg->max_connections / 2,
                                   cfg->max_connections_per_ip >= 4 ? cfg->max_connections_per_ip / 4 : 1);
    if (!svc->heads) {
        texopt_fail(err, err_len, TEXOPT_E_NOMEM, "out of memory");
        return NULL;
    }
    memset(&svc->mhd_log, 0, sizeof svc->mhd_log);
    pthread_mutex_init(&svc->mhd_log.mu, NULL);
    struct MHD_Daemon *d = MHD_start_daemon(
        flags, (uint16_t)svc->config.port, NULL, NULL, on_request, svc, MHD_OPTION_EXTERNAL_LOGGER, on_mhd_log,
        &svc->mhd_log, MHD_OPTION_SOCK_ADDR, (struct sockaddr *)&addr, MHD_OPTION_NOTIFY_COMPLETED, on_completed, svc,
        MHD_OPTION_NOTIFY_CONNECTION, on_connection, svc, MHD_OPTION_CONNECTION_LIMIT,
        (unsigned int)cfg->max_connections, MHD_OPTION_PER_IP_CONNECTION_LIMIT,
        (unsigned int)cfg->max_connections_per_ip, MHD_OPTION_CONNECTION_TIMEOUT,
        (unsigned int)cfg->idle_timeout_seconds, MHD_OPTION_CONNECTION_MEMORY_LIMIT, HEAD_MEMORY_BYTES,
        MHD_OPTION_THREAD_STACK_SIZE, TEXOPT_PARSE_STACK_BYTES, MHD_OPTION_END);
    if (!d) {
        head_watch_destroy(svc->heads);
        svc->heads = NULL;
        pthread_mutex_destroy(&svc->mhd_log.mu);
        texopt_fail(err, err_len, TEXOPT_E_IO, "cannot listen on %s:%d (address in use or not permitted)",
                    svc->config.bind, svc->config.port);
        return NULL;
    }
    const union MHD_DaemonInfo *info = MHD_get_daemon_info(d, MHD_DAEMON_INFO_BIND_PORT);
    *port_out = info ? info->port : svc->config.port;
    return d;
}

void api_http_quiesce(struct MHD_Daemon *daemon)
{
    MHD_socket s = MHD_quiesce_daemon(daemon);
    if (s != MHD_INVALID_SOCKET)
        close(s);
}

void api_http_drain_streams(api_service *svc, int timeout_ms)
{
    struct timespec step = {0, 10 * 1000000L};
    for (int waited = 0; atomic_load(&svc->open_streams) > 0 && waited < timeout_ms; waited += 10)
        nanosleep(&step, NULL);
}

int api_http_sweep(api_service *svc)
{
    return svc->heads ? head_watch_sweep(svc->heads, monotonic_seconds()) : 0;
}

void api_http_stop(api_service *svc, struct MHD_Daemon *daemon)
{
    if (daemon)
        MHD_stop_daemon(daemon);
    head_watch_destroy(svc->heads);
    svc->heads = NULL;
    pthread_mutex_destroy(&svc->mhd_log.mu);
}
