/* fuzz_multipart.c - libFuzzer harness: the upload parser (api/upload.c) fed a
 * multipart/form-data body the way texoptd feeds it, through a libmicrohttpd connection.
 *
 * The post processor needs a real connection (it reads the boundary from its Content-Type
 * header), so one daemon without a listening socket is started once and each input is a
 * request handed to it over a socketpair (MHD_add_connection) and run to its end. An input
 * is: the Content-Type value up to the first newline, then one byte that sets the size of
 * the pieces the body is fed in (1 .. 255; 0: as libmicrohttpd delivers it), then the body.
 * Each request uploads into a fresh directory under /dev/shm, removed afterwards.
 * Properties checked beyond memory safety: the upload counts every body byte, a failure has
 * an HTTP status of 400 .. 599 and a detail, and a finished upload's model file exists.
 * Does not: run the rest of the service (jobs.c, the model check: fuzz_gltf.c). */
#define _DEFAULT_SOURCE
#include <errno.h>
#include <limits.h>
#include <microhttpd.h>
#include <netinet/in.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fsutil.h"
#include "upload.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define UPLOAD_LIMIT (1u << 20)

typedef struct request_state {
    char dir[64];
    size_t piece;          /* feed size; 0 = whatever libmicrohttpd delivers */
    size_t body_len;
    api_upload *upload;
    int began;
} request_state;

static void check(int ok)
{
    if (!ok)
        __builtin_trap();
}

static void check_failure(const api_upload *u)
{
    const char *slug, *detail;
    int status = api_upload_error(u, &slug, &detail);
    check(status >= 400 && status <= 599 && slug && detail && detail[0]);
}

static void check_finished(request_state *st)
{
    if (api_upload_finish(st->upload) != 0) {
        check_failure(st->upload);
        return;
    }
    check(api_upload_bytes(st->upload) == st->body_len);
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/%s", st->dir, api_upload_model_rel(st->upload));
    struct stat sb;
    check(stat(path, &sb) == 0 && S_ISREG(sb.st_mode));
    size_t params_len;
    const char *params = api_upload_params(st->upload, &params_len);
    check(!params || (params_len <= API_UPLOAD_MAX_PARAMS && strlen(params) <= params_len));
}

static enum MHD_Result answer(void *cls, struct MHD_Connection *c, const char *url, const char *method,
                              const char *version, const char *upload_data, size_t *upload_data_size,
                              void **req_cls)
{
    (void)cls;
    (void)url;
    (void)method;
    (void)version;
    request_state *st = *req_cls;
    if (!st->began) {
        st->began = 1;
        int status = 0;
        const char *slug = "";
        char detail[300] = "";
        st->upload = api_upload_begin(st->dir, 1, c, UPLOAD_LIMIT, &status, &slug, detail, sizeof detail);
        check(st->upload || (status >= 400 && detail[0]));
        return MHD_YES;
    }
    if (*upload_data_size > 0) {
        size_t n = *upload_data_size;
        if (st->piece && n > st->piece)
            n = st->piece;
        if (st->upload)
            api_upload_feed(st->upload, upload_data, n);
        *upload_data_size -= n;
        return MHD_YES;
    }
    if (st->upload)
        check_finished(st);
    struct MHD_Response *r = MHD_create_response_from_buffer(0, (void *)"", MHD_RESPMEM_PERSISTENT);
    enum MHD_Result ok = MHD_queue_response(c, 200, r);
    MHD_destroy_response(r);
    return ok;
}

static request_state *current;

/* The request state comes from the harness, not from the URL: one request per connection. */
static void *log_uri(void *cls, const char *uri, struct MHD_Connection *c)
{
    (void)cls;
    (void)uri;
    (void)c;
    return current;
}

static struct MHD_Daemon *daemon_once(void)
{
    static struct MHD_Daemon *d;
    if (!d)
        d = MHD_start_daemon(MHD_USE_NO_LISTEN_SOCKET, 0, NULL, NULL, answer, NULL,
                             MHD_OPTION_URI_LOG_CALLBACK, log_uri, NULL, MHD_OPTION_CONNECTION_TIMEOUT,
                             (unsigned)10, MHD_OPTION_END);
    check(d != NULL);
    return d;
}

/* Writes the request while running the daemon, then drains the reply until it closes. */
static void exchange(struct MHD_Daemon *d, int fd, const char *req, size_t len)
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
            return;
    }
    check(0); /* the daemon neither answered nor closed */
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const uint8_t *newline = memchr(data, '\n', size);
    if (!newline || newline + 1 >= data + size)
        return 0;
    size_t type_len = (size_t)(newline - data);
    if (memchr(data, '\r', type_len) || memchr(data, '\0', type_len))
        return 0; /* one header line, as HTTP allows */
    request_state st;
    memset(&st, 0, sizeof st);
    st.piece = newline[1];
    const uint8_t *body = newline + 2;
    st.body_len = size - (size_t)(body - data);

    char head[512];
    int head_len = snprintf(head, sizeof head,
                            "POST /v1/jobs HTTP/1.1\r\nHost: fuzz\r\nContent-Type: %.*s\r\n"
                            "Content-Length: %zu\r\nConnection: close\r\n\r\n",
                            (int)(type_len < 300 ? type_len : 300), (const char *)data, st.body_len);
    size_t req_len = (size_t)head_len + st.body_len;
    char *req = malloc(req_len);
    check(req != NULL);
    memcpy(req, head, (size_t)head_len);
    memcpy(req + head_len, body, st.body_len);

    snprintf(st.dir, sizeof st.dir, "/dev/shm/texopt_fuzz_XXXXXX");
    check(mkdtemp(st.dir) != NULL);
    struct MHD_Daemon *d = daemon_once();
    int fds[2];
    check(socketpair(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0, fds) == 0);
    struct sockaddr_in peer = {.sin_family = AF_INET, .sin_addr.s_addr = htonl(INADDR_LOOPBACK)};
    current = &st;
    check(MHD_add_connection(d, fds[1], (const struct sockaddr *)&peer, sizeof peer) == MHD_YES);
    exchange(d, fds[0], req, req_len);
    close(fds[0]);
    MHD_run(d); /* lets the daemon see the close and free the connection */
    api_upload_destroy(st.upload);
    fs_remove_tree(st.dir);
    free(req);
    return 0;
}
