/* upload_driver.h - api/upload.c fed a request body the way texoptd feeds it, through a real
 * libmicrohttpd connection, in process (header only: tests/fuzz/fuzz_multipart.c and
 * tests/unit/test_upload_multipart.c).
 *
 * The post processor needs a connection (it reads the boundary from the Content-Type
 * header), so one daemon without a listening socket is started once and each request is
 * handed to it over a socketpair (MHD_add_connection) and run to its end on the calling
 * thread. The handler hands the body to api_upload_feed in pieces of at most `piece` bytes
 * (0: as libmicrohttpd delivers them), so a test chooses where the body is cut.
 * Does not: run the rest of the service (jobs.c: routes, auth, the model check). */
#ifndef TEXOPT_TEST_UPLOAD_DRIVER_H
#define TEXOPT_TEST_UPLOAD_DRIVER_H

#include <errno.h>
#include <microhttpd.h>
#include <netinet/in.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "upload.h"

/* What one request left in its upload. */
typedef struct upload_outcome {
    int began;  /* 0: libmicrohttpd refused the request before the handler ran */
    int status; /* api_upload_error's status, 0 when the upload finished */
    char slug[64], detail[300];
    char model_rel[300];
    char *params; /* the params part, or NULL */
    uint64_t bytes, digest;
} upload_outcome;

typedef struct upload_request {
    const char *dir;
    size_t piece;
    api_upload *upload;
    int began;
    int status; /* api_upload_begin's refusal */
    const char *slug;
    char detail[300];
} upload_request;

static inline void upload_outcome_free(upload_outcome *out)
{
    free(out->params);
    out->params = NULL;
}

static inline enum MHD_Result upload_driver_answer(void *cls, struct MHD_Connection *c, const char *url,
                                                   const char *method, const char *version, const char *upload_data,
                                                   size_t *upload_data_size, void **req_cls)
{
    (void)cls;
    (void)url;
    (void)method;
    (void)version;
    upload_request *rq = *req_cls;
    if (!rq->began) {
        rq->began = 1;
        rq->upload = api_upload_begin(rq->dir, 1, c, 1u << 20, &rq->status, &rq->slug, rq->detail, sizeof rq->detail);
        return MHD_YES;
    }
    if (*upload_data_size > 0) {
        size_t n = *upload_data_size;
        if (rq->piece && n > rq->piece)
            n = rq->piece;
        if (rq->upload)
            api_upload_feed(rq->upload, upload_data, n);
        *upload_data_size -= n;
        return MHD_YES;
    }
    if (rq->upload)
        api_upload_finish(rq->upload);
    struct MHD_Response *r = MHD_create_response_from_buffer(0, (void *)"", MHD_RESPMEM_PERSISTENT);
    enum MHD_Result ok = MHD_queue_response(c, 200, r);
    MHD_destroy_response(r);
    return ok;
}

/* The request is the one in flight: one request per connection, one connection at a time. */
static upload_request *upload_driver_current;

static inline void *upload_driver_request(void *cls, const char *uri, struct MHD_Connection *c)
{
    (void)cls;
    (void)uri;
    (void)c;
    return upload_driver_current;
}

static inline struct MHD_Daemon *upload_driver_daemon(void)
{
    static struct MHD_Daemon *d;
    if (!d)
        d = MHD_start_daemon(MHD_USE_NO_LISTEN_SOCKET, 0, NULL, NULL, upload_driver_answer, NULL,
                             MHD_OPTION_URI_LOG_CALLBACK, upload_driver_request, NULL, MHD_OPTION_CONNECTION_TIMEOUT,
                             (unsigned)10, MHD_OPTION_END);
    return d;
}

/* Writes the request while running the daemon, then drains the reply until it closes.
 * Returns 0, or -1 when the daemon neither answered nor closed. */
static inline int upload_driver_exchange(struct MHD_Daemon *d, int fd, const char *req, size_t len)
{
    size_t sent = 0;
    char reply[4096];
    for (int rounds = 0; rounds < 100000; rounds++) {
        if (sent < len) {
            ssize_t n = write(fd, req + sent, len - sent);
            if (n > 0)
                sent += (size_t)n;
        }
        MHD_run(d);
        ssize_t got = read(fd, reply, sizeof reply);
        if (got == 0 || (got < 0 && errno != EAGAIN && errno != EWOULDBLOCK))
            return 0;
    }
    return -1;
}

/* POSTs body with the given Content-Type (one header line), uploading into dir (which must
 * exist), fed in pieces of at most piece bytes. Fills *out (free with upload_outcome_free).
 * Returns 0, or -1 when the request could not be run. */
static inline int upload_drive(const char *content_type, const void *body, size_t body_len, size_t piece,
                               const char *dir, upload_outcome *out)
{
    memset(out, 0, sizeof *out);
    struct MHD_Daemon *d = upload_driver_daemon();
    if (!d)
        return -1;
    char head[512];
    int head_len = snprintf(head, sizeof head,
                            "POST /v1/jobs HTTP/1.1\r\nHost: test\r\nContent-Type: %.300s\r\n"
                            "Content-Length: %zu\r\nConnection: close\r\n\r\n",
                            content_type, body_len);
    size_t req_len = (size_t)head_len + body_len;
    char *req = malloc(req_len);
    int fds[2];
    if (!req || socketpair(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0, fds) != 0) {
        free(req);
        return -1;
    }
    memcpy(req, head, (size_t)head_len);
    memcpy(req + head_len, body, body_len);
    upload_request rq = {.dir = dir, .piece = piece, .slug = ""};
    struct sockaddr_in peer = {.sin_family = AF_INET, .sin_addr.s_addr = htonl(INADDR_LOOPBACK)};
    upload_driver_current = &rq;
    int rc = MHD_add_connection(d, fds[1], (const struct sockaddr *)&peer, sizeof peer) == MHD_YES ? 0 : -1;
    if (rc == 0)
        rc = upload_driver_exchange(d, fds[0], req, req_len);
    close(fds[0]);
    MHD_run(d); /* lets the daemon see the close and free the connection */
    upload_driver_current = NULL;
    free(req);

    out->began = rq.began;
    out->status = rq.status;
    snprintf(out->slug, sizeof out->slug, "%s", rq.slug);
    snprintf(out->detail, sizeof out->detail, "%s", rq.detail);
    if (rq.upload) {
        const char *slug, *detail;
        out->status = api_upload_error(rq.upload, &slug, &detail);
        snprintf(out->slug, sizeof out->slug, "%s", out->status ? slug : "");
        snprintf(out->detail, sizeof out->detail, "%s", out->status ? detail : "");
        snprintf(out->model_rel, sizeof out->model_rel, "%s", api_upload_model_rel(rq.upload));
        size_t len;
        const char *params = api_upload_params(rq.upload, &len);
        out->params = params ? strdup(params) : NULL;
        out->bytes = api_upload_bytes(rq.upload);
        out->digest = api_upload_digest(rq.upload);
    }
    api_upload_destroy(rq.upload);
    return rc;
}

#endif
