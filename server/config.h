/* config.h - texoptd's configuration: defaults, then environment, then flags.
 *
 * Every setting has a flag and a TEXOPT_* environment variable (flags win):
 *   --bind ADDR            TEXOPT_BIND             127.0.0.1 (loopback unless asked)
 *   --port N               TEXOPT_PORT             8080 (0 = any free port, printed in the log)
 *   --data-dir DIR         TEXOPT_DATA_DIR         ./texopt-data
 *   --workers N            TEXOPT_WORKERS          1 (jobs running at once)
 *   --threads-per-job N    TEXOPT_THREADS_PER_JOB  0 = every core
 *   --queue-limit N        TEXOPT_QUEUE_LIMIT      16 queued jobs, then 503 + Retry-After
 *   --max-upload-bytes N   TEXOPT_MAX_UPLOAD_BYTES 268435456 (256 MiB per request body)
 *   --max-pixels N         TEXOPT_MAX_PIXELS       268435456 decoded texels over all images
 *   --retention-seconds N  TEXOPT_RETENTION_SECONDS 604800 (finished jobs kept a week; 0 = forever)
 *   --max-connections N    TEXOPT_MAX_CONNECTIONS  512
 *   --max-connections-per-ip N  TEXOPT_MAX_CONNECTIONS_PER_IP  64 open connections per client address
 *   --header-timeout S     TEXOPT_HEADER_TIMEOUT   10 s to send the request line and headers, in all
 *   --idle-timeout S       TEXOPT_IDLE_TIMEOUT     30 s without a byte from the client (body, keep-alive)
 *   --memory-budget N      TEXOPT_MEMORY_BUDGET    bytes running jobs may take by estimate
 *                                                  (server/memory_budget.h); default half the RAM
 *   --cors-origin LIST     TEXOPT_CORS_ORIGIN      unset = no CORS headers; "*", or origins
 *                                                  separated by commas (the request's is echoed)
 *   --web-dir DIR          TEXOPT_WEB_DIR          the page's files (web/ of the source tree,
 *                                                  or /usr/share/texopt/web when installed)
 *   --port-file PATH       TEXOPT_PORT_FILE        unset; where to write the bound port
 *   --store URL            TEXOPT_STORE            unset = jobs on disk in --data-dir; a
 *                                                  postgresql:// URL = jobs in that database,
 *                                                  shared by every node given the same URL
 *   --blob-dir DIR         TEXOPT_BLOB_DIR         with --store: the directory every node
 *                                                  shares for uploads and results (default --data-dir)
 *   --lease-seconds N      TEXOPT_LEASE_SECONDS    30: with --store, a running job whose node
 *                                                  sent no heartbeat for this long runs again elsewhere
 *   --max-attempts N       TEXOPT_MAX_ATTEMPTS     3: with --store, runs a job may start before
 *                                                  lost leases mark it failed
 *   (no flag)              TEXOPT_API_TOKEN        unset = no authentication
 * The token is only read from the environment so that it never shows in `ps`. */
#ifndef TEXOPT_SERVER_CONFIG_H
#define TEXOPT_SERVER_CONFIG_H

#include <stddef.h>
#include <stdint.h>

typedef struct service_config {
    char bind[64];
    int port;
    char data_dir[1024];
    int workers;
    int threads_per_job;
    int queue_limit;
    uint64_t max_upload_bytes;
    uint64_t max_pixels;
    int64_t retention_seconds;
    int max_connections;
    int max_connections_per_ip;
    int header_timeout_seconds;
    int idle_timeout_seconds;
    uint64_t memory_budget;
    char cors_origin[1024];
    char web_dir[1024];
    char port_file[1024];
    char store[1024];
    char blob_dir[1024];
    int lease_seconds;
    int max_attempts;
    char api_token[256];
} service_config;

void config_defaults(service_config *cfg);

/* Applies the TEXOPT_* variables from the process environment. Returns 0, or -1 with a
 * message naming the bad variable. */
int config_apply_env(service_config *cfg, char *err, size_t err_len);

/* Applies command-line flags. Returns 0, 1 when --help was asked (usage printed by the
 * caller from config_usage()), or -1 with a message naming the bad flag. */
int config_apply_args(service_config *cfg, int argc, char **argv, char *err, size_t err_len);

/* The usage text listing every flag. */
const char *config_usage(void);

#endif
