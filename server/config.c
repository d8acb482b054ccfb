/* config.c - parsing texoptd's flags and environment (see config.h for the list). */
#define _DEFAULT_SOURCE
#include "config.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "texopt.h"

#ifndef TEXOPT_WEB_DEFAULT
#define TEXOPT_WEB_DEFAULT "/usr/share/texopt/web"
#endif

void config_defaults(service_config *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    snprintf(cfg->bind, sizeof cfg->bind, "127.0.0.1");
    cfg->port = 8080;
    snprintf(cfg->data_dir, sizeof cfg->data_dir, "./texopt-data");
    snprintf(cfg->web_dir, sizeof cfg->web_dir, "%s", TEXOPT_WEB_DEFAULT);
    cfg->workers = 1;
    cfg->threads_per_job = 0;
    cfg->queue_limit = 16;
    cfg->max_upload_bytes = 256ull << 20;
    cfg->max_pixels = 1ull << 28;
    cfg->retention_seconds = 7 * 24 * 3600;
    cfg->max_connections = 512;
    cfg->max_connections_per_ip = 64;
    cfg->header_timeout_seconds = 10;
    cfg->idle_timeout_seconds = 30;
    cfg->lease_seconds = 30;
    cfg->max_attempts = 3;
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    cfg->memory_budget = pages > 0 && page > 0 ? (uint64_t)pages * (uint64_t)page / 2 : 4ull << 30;
}

static int parse_int(const char *text, long long lo, long long hi, long long *out)
{
    if (!text || !*text)
        return -1;
    char *end;
    errno = 0;
    long long v = strtoll(text, &end, 10);
    if (errno || *end || v < lo || v > hi)
        return -1;
    *out = v;
    return 0;
}

typedef enum { KIND_STRING, KIND_INT, KIND_U64, KIND_I64 } setting_kind;

typedef struct setting {
    const char *flag, *env;
    setting_kind kind;
    size_t offset, size;
    long long lo, hi;
} setting;

#define STR_SETTING(f, e, field)                                                                                       \
    {                                                                                                                  \
        f, e, KIND_STRING, offsetof(service_config, field), sizeof(((service_config *)0)->field), 0, 0                 \
    }
#define INT_SETTING(f, e, field, lo, hi)                                                                               \
    {                                                                                                                  \
        f, e, KIND_INT, offsetof(service_config, field), 0, lo, hi                                                     \
    }

static const setting settings[] = {
    STR_SETTING("--bind", "TEXOPT_BIND", bind),
    INT_SETTING("--port", "TEXOPT_PORT", port, 0, 65535),
    STR_SETTING("--data-dir", "TEXOPT_DATA_DIR", data_dir),
    INT_SETTING("--workers", "TEXOPT_WORKERS", workers, 1, 64),
    INT_SETTING("--threads-per-job", "TEXOPT_THREADS_PER_JOB", threads_per_job, 0, 1024),
    INT_SETTING("--queue-limit", "TEXOPT_QUEUE_LIMIT", queue_limit, 1, 100000),
    {"--max-upload-bytes", "TEXOPT_MAX_UPLOAD_BYTES", KIND_U64, offsetof(service_config, max_upload_bytes), 0, 1,
     LLONG_MAX},
    {"--max-pixels", "TEXOPT_MAX_PIXELS", KIND_U64, offsetof(service_config, max_pixels), 0, 1, LLONG_MAX},
    {"--retention-seconds", "TEXOPT_RETENTION_SECONDS", KIND_I64, offsetof(service_config, retention_seconds), 0, 0,
     LLONG_MAX},
    INT_SETTING("--max-connections", "TEXOPT_MAX_CONNECTIONS", max_connections, 4, 100000),
    INT_SETTING("--max-connections-per-ip", "TEXOPT_MAX_CONNECTIONS_PER_IP", max_connections_per_ip, 1, 100000),
    INT_SETTING("--header-timeout", "TEXOPT_HEADER_TIMEOUT", header_timeout_seconds, 1, 3600),
    INT_SETTING("--idle-timeout", "TEXOPT_IDLE_TIMEOUT", idle_timeout_seconds, 1, 86400),
    {"--memory-budget", "TEXOPT_MEMORY_BUDGET", KIND_U64, offsetof(service_config, memory_budget), 0, 1, LLONG_MAX},
    STR_SETTING("--cors-origin", "TEXOPT_CORS_ORIGIN", cors_origin),
    STR_SETTING("--port-file", "TEXOPT_PORT_FILE", port_file),
    STR_SETTING("--web-dir", "TEXOPT_WEB_DIR", web_dir),
    STR_SETTING("--store", "TEXOPT_STORE", store),
    STR_SETTING("--blob-dir", "TEXOPT_BLOB_DIR", blob_dir),
    INT_SETTING("--lease-seconds", "TEXOPT_LEASE_SECONDS", lease_seconds, 2, 3600),
    INT_SETTING("--max-attempts", "TEXOPT_MAX_ATTEMPTS", max_attempts, 1, 100),
    STR_SETTING(NULL, "TEXOPT_API_TOKEN", api_token),
};
#define SETTING_COUNT (sizeof settings / sizeof settings[0])

static int apply(service_config *cfg, const setting *s, const char *value, const char *name, char *err, size_t err_len)
{
    char *field = (char *)cfg + s->offset;
    long long v;
    switch (s->kind) {
    case KIND_STRING:
        if (strlen(value) >= s->size)
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "%s: value longer than %zu bytes", name,
                               s->size - 1),
                   -1;
        memcpy(field, value, strlen(value) + 1);
        return 0;
    case KIND_INT:
        if (parse_int(value, s->lo, s->hi, &v) != 0)
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "%s: '%s' is not an integer in %lld .. %lld",
                               name, value, s->lo, s->hi),
                   -1;
        *(int *)(void *)field = (int)v;
        return 0;
    case KIND_U64:
        if (parse_int(value, s->lo, s->hi, &v) != 0)
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "%s: '%s' is not a positive integer", name,
                               value),
                   -1;
        *(uint64_t *)(void *)field = (uint64_t)v;
        return 0;
    case KIND_I64:
        if (parse_int(value, s->lo, s->hi, &v) != 0)
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "%s: '%s' is not a non-negative integer", name,
                               value),
                   -1;
        *(int64_t *)(void *)field = (int64_t)v;
        return 0;
    }
    return -1;
}

int config_apply_env(service_config *cfg, char *err, size_t err_len)
{
    for (size_t i = 0; i < SETTING_COUNT; i++) {
        const char *value = getenv(settings[i].env);
        if (value && *value && apply(cfg, &settings[i], value, settings[i].env, err, err_len) != 0)
            return -1;
    }
    return 0;
}

int config_apply_args(service_config *cfg, int argc, char **argv, char *err, size_t err_len)
{
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
            return 1;
        const setting *s = NULL;
        const char *value = NULL;
        for (size_t k = 0; k < SETTING_COUNT && !s; k++) {
            if (!settings[k].flag)
                continue;
            size_t n = strlen(settings[k].flag);
            if (strcmp(argv[i], settings[k].flag) == 0) {
                if (i + 1 >= argc)
                    return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "%s needs a value", argv[i]), -1;
                s = &settings[k];
                value = argv[++i];
            } else if (strncmp(argv[i], settings[k].flag, n) == 0 && argv[i][n] == '=') {
                s = &settings[k];
                value = argv[i] + n + 1;
            }
        }
        if (!s)
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "unknown flag '%s' (see --help)", argv[i]), -1;
        if (apply(cfg, s, value, s->flag, err, err_len) != 0)
            return -1;
    }
    return 0;
}

const char *config_usage(void)
{
    return "usage: texoptd [--bind ADDR] [--port N] [--data-dir DIR] [--workers N]\n"
           "               [--threads-per-job N] [--queue-limit N] [--max-upload-bytes N]\n"
           "               [--max-pixels N] [--retention-seconds N] [--max-connections N]\n"
           "               [--max-connections-per-ip N] [--header-timeout S] [--idle-timeout S]\n"
           "               [--memory-budget BYTES] [--cors-origin LIST] [--port-file PATH]\n"
           "               [--web-dir DIR] [--store postgresql://...] [--blob-dir DIR]\n"
           "               [--lease-seconds N] [--max-attempts N]\n"
           "Slow clients: at most --max-connections-per-ip (64) connections per address, the\n"
           "request line and headers within --header-timeout seconds (10) in all, and no more\n"
           "than --idle-timeout seconds (30) without a byte. Jobs run while the memory their\n"
           "images need by estimate fits in --memory-budget (default half the RAM).\n"
           "Each flag has a TEXOPT_* environment variable (--data-dir: TEXOPT_DATA_DIR);\n"
           "TEXOPT_API_TOKEN (environment only) turns on bearer-token authentication.\n"
           "Many nodes: --store postgresql://user@host/db (or TEXOPT_STORE, which keeps a\n"
           "password out of `ps`) keeps jobs in PostgreSQL and uploads and results in the\n"
           "--blob-dir every node mounts; see docs/api.md, \"Deployment\".\n";
}
