/* main.c - texoptd: the texopt HTTP service (issue 5; the engine implements Sun et al.
 * 2022, "Efficient Texture Parameterization Driven by Perceptual-Loss-on-Screen").
 *
 * Threads: the main thread only waits for signals (and expires old jobs once a minute);
 * libmicrohttpd runs one thread per connection (api/http.c); config.workers worker threads
 * run jobs (server/workers.c). Start-up re-queues every job found queued or interrupted on
 * disk (server/store.c). SIGTERM/SIGINT: stop accepting connections, fail /readyz, cancel
 * running jobs back to "queued" at their next checkpoint, end event streams, wait for open
 * requests, exit 0. A kill -9 loses nothing accepted either: the next start re-runs it. */
#define _DEFAULT_SOURCE
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "config.h"
#include "fsutil.h"
#include "log.h"
#include "metrics.h"
#include "queue.h"
#include "service.h"
#include "store.h"
#include "texopt.h"
#include "workers.h"

#ifndef TEXOPT_OPENAPI_DEFAULT
#define TEXOPT_OPENAPI_DEFAULT "/usr/share/texopt/openapi.yaml"
#endif

#define EXPIRE_EVERY_SECONDS 60

static int requeue_restored(job_store *store, job_queue *queue)
{
    char(*ids)[JOB_ID_LEN + 1] = NULL;
    int n = store_queued_ids(store, &ids);
    for (int i = 0; i < n; i++)
        queue_push(queue, ids[i], 1);
    free(ids);
    return n;
}

static int write_port_file(const char *path, int port)
{
    char text[16];
    int n = snprintf(text, sizeof text, "%d\n", port);
    return fs_write_atomic(path, text, (size_t)n);
}

/* Blocks until SIGTERM or SIGINT, running the retention sweep meanwhile. */
static void wait_for_stop(const sigset_t *signals, api_service *svc)
{
    struct timespec tick = {1, 0};
    time_t last_expire = 0;
    for (;;) {
        int sig = sigtimedwait(signals, NULL, &tick);
        if (sig == SIGTERM || sig == SIGINT) {
            log_event("level=info event=shutdown signal=%s", sig == SIGTERM ? "SIGTERM" : "SIGINT");
            return;
        }
        store_retry_unsaved(svc->store); /* ends of runs a full disk kept from job.json */
        int cut = api_http_sweep(svc);
        if (cut > 0)
            log_event("level=warn event=slow-heads cut=%d", cut);
        time_t now = time(NULL);
        if (svc->config.retention_seconds > 0 && now - last_expire >= EXPIRE_EVERY_SECONDS) {
            last_expire = now;
            int n = store_expire(svc->store, store_now_ms(), svc->config.retention_seconds * 1000);
            if (n > 0)
                log_event("level=info event=expire jobs=%d", n);
        }
    }
}

static int fail_start(const char *what, const char *err)
{
    char quoted[600];
    log_event("level=error event=start failed=%s error=%s", what, log_quote(quoted, sizeof quoted, err));
    return 1;
}

int main(int argc, char **argv)
{
    /* Before any engine thread exists (library_threads.h says why). */
    texopt_limit_library_threads();

    api_service svc;
    memset(&svc, 0, sizeof svc);
    char err[2048] = "";
    config_defaults(&svc.config);
    if (config_apply_env(&svc.config, err, sizeof err) != 0) {
        fprintf(stderr, "texoptd: %s\n", err);
        return 2;
    }
    int args = config_apply_args(&svc.config, argc, argv, err, sizeof err);
    if (args != 0) {
        if (args < 0)
            fprintf(stderr, "texoptd: %s\n", err);
        fputs(config_usage(), args < 0 ? stderr : stdout);
        return args < 0 ? 2 : 0;
    }

    /* Signals are taken synchronously by this thread only: every thread made from here on
     * inherits the blocked mask. A client that hangs up must not kill us with SIGPIPE. */
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGTERM);
    sigaddset(&signals, SIGINT);
    pthread_sigmask(SIG_BLOCK, &signals, NULL);
    signal(SIGPIPE, SIG_IGN);

    const char *openapi_path = getenv("TEXOPT_OPENAPI_FILE");
    size_t openapi_len = 0;
    char *openapi = fs_read_small(openapi_path ? openapi_path : TEXOPT_OPENAPI_DEFAULT, 4u << 20, &openapi_len);
    if (!openapi)
        log_event("level=warn event=start openapi=missing path=%s",
                  openapi_path ? openapi_path : TEXOPT_OPENAPI_DEFAULT);
    svc.openapi = openapi;
    svc.openapi_len = openapi_len;

    if (fs_mkdir_p(svc.config.data_dir) != 0) {
        snprintf(err, sizeof err, "cannot create %s: %s", svc.config.data_dir, strerror(errno));
        return fail_start("data-dir", err);
    }
    svc.store = store_open_config(&svc.config, err, sizeof err);
    svc.queue = queue_create(svc.config.queue_limit);
    svc.metrics = metrics_create();
    if (!svc.store || !svc.queue || !svc.metrics)
        return fail_start("store", err[0] ? err : "out of memory");
    /* A shared store's queued jobs are in its database, not this node's queue. */
    int restored = store_shared(svc.store) ? 0 : requeue_restored(svc.store, svc.queue);
    svc.workers = workers_start(svc.store, svc.queue, svc.metrics, &svc.config, err, sizeof err);
    if (!svc.workers)
        return fail_start("workers", err);
    int port = 0;
    struct MHD_Daemon *daemon = api_http_start(&svc, &port, err, sizeof err);
    if (!daemon)
        return fail_start("http", err);
    if (svc.config.port_file[0] && write_port_file(svc.config.port_file, port) != 0)
        return fail_start("port-file", strerror(errno));
    log_event("level=info event=listening bind=%s port=%d data_dir=%s store=%s workers=%d queue_limit=%d "
              "restored=%d auth=%s",
              svc.config.bind, port, svc.config.data_dir, store_kind(svc.store), svc.config.workers,
              svc.config.queue_limit, restored, svc.config.api_token[0] ? "bearer" : "none");

    wait_for_stop(&signals, &svc);

    atomic_store(&svc.draining, 1);
    api_http_quiesce(daemon);
    workers_stop(svc.workers);
    store_wake_all(svc.store);
    api_http_drain_streams(&svc, 2000);
    api_http_stop(&svc, daemon);
    workers_destroy(svc.workers);
    queue_destroy(svc.queue);
    store_close(svc.store);
    metrics_destroy(svc.metrics);
    free(openapi);
    log_event("level=info event=stopped");
    return 0;
}
