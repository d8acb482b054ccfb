/* service.h - what the HTTP layer shares with the rest of texoptd.
 *
 * One api_service is made by api/main.c and outlives the HTTP daemon; the HTTP threads
 * read the configuration and call into the store, the queue and the metrics, which do
 * their own locking. No globals: libmicrohttpd hands this pointer to every callback. */
#ifndef TEXOPT_API_SERVICE_H
#define TEXOPT_API_SERVICE_H

#include <pthread.h>
#include <stdatomic.h>
#include <stddef.h>

#include "config.h"
#include "metrics.h"
#include "queue.h"
#include "store.h"

struct worker_pool;
struct head_watch;

/* libmicrohttpd's own log lines written this second, and those dropped (api/http.c). */
typedef struct api_log_limit {
    pthread_mutex_t mu;
    long second;
    int written;
    long long dropped;
} api_log_limit;

typedef struct api_service {
    service_config config;
    job_store *store;
    job_queue *queue;
    service_metrics *metrics;
    struct worker_pool *workers; /* NULL in tests without workers */
    atomic_int draining;         /* set at SIGTERM: no new jobs, /readyz fails */
    atomic_int open_streams;     /* event streams whose response is not freed yet */
    struct head_watch *heads;    /* connections sending a request head (api/head_watch.h) */
    api_log_limit mhd_log;
    const char *openapi; /* the contents of openapi.yaml, served as is */
    size_t openapi_len;
} api_service;

struct MHD_Daemon;

/* Starts the HTTP daemon on config.bind:config.port (thread per connection, see http.c).
 * *port_out gets the bound port (useful with port 0). NULL with a message on failure. */
struct MHD_Daemon *api_http_start(api_service *svc, int *port_out, char *err, size_t err_len);

/* Stops accepting connections; requests already connected finish. */
void api_http_quiesce(struct MHD_Daemon *daemon);

/* After store_wake_all: waits (at most timeout_ms) until every event stream has sent its
 * end, so that stopping the daemon does not cut one off mid-chunk. */
void api_http_drain_streams(api_service *svc, int timeout_ms);

/* Cuts the connections whose request head is past --header-timeout. Returns how many;
 * called once a second. */
int api_http_sweep(api_service *svc);

/* Waits for every connection to end and frees the daemon (event streams end when the store
 * is woken with store_wake_all first). Accepts a NULL daemon. */
void api_http_stop(api_service *svc, struct MHD_Daemon *daemon);

#endif
