/* jobs.c - the /v1/jobs routes: upload (POST), list, get, cancel/delete, and the job's files.
 * The upload path follows systemd-journal-remote: decide from the headers, stream the body
 * to disk, then validate and hand the job to the queue. */
#define _DEFAULT_SOURCE
#include "http_internal.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fingerprint.h"
#include "fsutil.h"
#include "job_json.h"
#include "model_check.h"
#include "params_json.h"
#include "problem.h"

/* Seconds a client should wait before asking again about an unfinished job. */
#define POLL_RETRY_SECONDS 1
/* Seconds to wait before retrying an upload refused because the queue is full. */
#define QUEUE_FULL_RETRY_SECONDS 30
/* Seconds to wait before retrying what could not be stored (a full disk). */
#define STORAGE_RETRY_SECONDS 30
/* After a failed upload the rest of the body is read and dropped (libmicrohttpd answers only
 * once the request is complete); past this many bytes the connection is cut instead. */
#define MAX_DISCARD_BYTES (64ull << 20)

static enum MHD_Result send_job(request_ctx *rq, struct MHD_Connection *c, int status, const job_record *job,
                                int location, int replayed)
{
    struct MHD_Response *r = http_response_owning(api_job_text(job), "application/json");
    if (!r)
        return MHD_NO;
    if (location) {
        char href[64];
        snprintf(href, sizeof href, "/v1/jobs/%s", job->id);
        MHD_add_response_header(r, "Location", href);
    }
    if (!job_state_finished(job->state)) {
        char seconds[16];
        snprintf(seconds, sizeof seconds, "%d", POLL_RETRY_SECONDS);
        MHD_add_response_header(r, "Retry-After", seconds);
    }
    if (replayed)
        MHD_add_response_header(r, "Idempotent-Replayed", "true");
    return http_send(rq, c, status, r);
}

/* 503 + Retry-After: the disk cannot take what the request needs stored, now. */
static enum MHD_Result storage_full(request_ctx *rq, struct MHD_Connection *c, const char *what)
{
    return http_send_problem(rq, c, 503, "storage-full", STORAGE_RETRY_SECONDS, "%s; retry later", what);
}

/* ---- POST /v1/jobs ------------------------------------------------------------------ */

static int media_type_is(const char *header, const char *type)
{
    size_t n = strlen(type);
    return header && strncasecmp(header, type, n) == 0 && (header[n] == '\0' || header[n] == ';' || header[n] == ' ');
}

enum MHD_Result jobs_post_headers(request_ctx *rq, struct MHD_Connection *c)
{
    api_service *svc = rq->svc;
    const char *key = MHD_lookup_connection_value(c, MHD_HEADER_KIND, "Idempotency-Key");
    if (key && strlen(key) > 128)
        return http_send_problem(rq, c, 400, "bad-idempotency-key", 0, "Idempotency-Key is longer than 128 bytes");
    /* A known key is answered once the body is in: only then can a retry be told from a
     * different request reusing the key. */
    job_record existing;
    rq->key_known = key && *key && store_find_key(svc->store, key, &existing) == STORE_OK;
    if (!rq->key_known && atomic_load(&svc->draining))
        return http_send_problem(rq, c, 503, "shutting-down", 5, "the service is shutting down; retry shortly");
    const char *type = MHD_lookup_connection_value(c, MHD_HEADER_KIND, MHD_HTTP_HEADER_CONTENT_TYPE);
    int raw = media_type_is(type, "model/gltf-binary");
    int multipart = media_type_is(type, "multipart/form-data");
    if (!raw && !multipart)
        return http_send_problem(rq, c, 415, "unsupported-media-type", 0,
                                 "Content-Type must be model/gltf-binary or multipart/form-data, not '%.80s'",
                                 type ? type : "(none)");
    const char *length = MHD_lookup_connection_value(c, MHD_HEADER_KIND, MHD_HTTP_HEADER_CONTENT_LENGTH);
    if (length && strtoull(length, NULL, 10) > svc->config.max_upload_bytes)
        return http_send_problem(rq, c, 413, "body-too-large", 0,
                                 "the body of %s bytes is larger than the limit of %llu bytes", length,
                                 (unsigned long long)svc->config.max_upload_bytes);
    if (!rq->key_known && store_unreachable(svc->store))
        return http_store_unreachable(rq, c);
    if (!rq->key_known && api_queue_depth(svc) >= queue_limit(svc->queue))
        return http_send_problem(rq, c, 503, "queue-full", QUEUE_FULL_RETRY_SECONDS,
                                 "the job queue is full (%d jobs waiting); retry later", queue_limit(svc->queue));
    if (!rq->key_known && !store_can_store(svc->store, length ? strtoull(length, NULL, 10) : 0))
        return storage_full(rq, c, "uploads cannot be stored now (the disk is full)");
    if (store_new_job_dir(svc->store, rq->job_id, rq->job_dir, sizeof rq->job_dir) != 0) {
        rq->job_id[0] = '\0';
        return http_send_problem(rq, c, 503, "storage-error", STORAGE_RETRY_SECONDS,
                                 "cannot create the job directory: %s", strerror(errno));
    }
    int status = 0;
    const char *slug = "";
    char detail[300];
    rq->upload = api_upload_begin(rq->job_dir, multipart, c, svc->config.max_upload_bytes, &status, &slug, detail,
                                  sizeof detail);
    if (!rq->upload)
        return http_send_problem(rq, c, status, slug, 0, "%s", detail);
    return MHD_YES;
}

enum MHD_Result jobs_post_body(request_ctx *rq, struct MHD_Connection *c, const char *data, size_t *size)
{
    (void)c;
    if (!rq->upload) {
        *size = 0;
        return MHD_YES;
    }
    const char *slug, *detail;
    if (api_upload_error(rq->upload, &slug, &detail)) {
        rq->discarded += *size;
        *size = 0;
        return rq->discarded > MAX_DISCARD_BYTES ? MHD_NO : MHD_YES;
    }
    api_upload_feed(rq->upload, data, *size);
    *size = 0;
    return MHD_YES;
}

/* Params from the multipart `params` part, or from the query string of a raw upload. */
static enum MHD_Result collect_query(void *cls, enum MHD_ValueKind kind, const char *key, const char *value)
{
    (void)kind;
    return api_params_add_text(cls, key, value) == 0 ? MHD_YES : MHD_NO;
}

static texopt_status read_params(request_ctx *rq, struct MHD_Connection *c, texopt_params *params, char *err,
                                 size_t err_len)
{
    size_t len;
    const char *text = api_upload_params(rq->upload, &len);
    cJSON *query = cJSON_CreateObject();
    if (!query)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "out of memory");
    MHD_get_connection_values(c, MHD_GET_ARGUMENT_KIND, collect_query, query);
    texopt_status s;
    if (text && query->child)
        s = texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                        "params: give them in the params part or in the query string, not both");
    else if (text)
        s = api_params_from_text(text, len, params, err, err_len);
    else
        s = api_params_from_json(query, params, err, err_len);
    cJSON_Delete(query);
    return s;
}

/* The server decides how many cores a job may use: a client asks for at most that. */
static void apply_thread_policy(const service_config *cfg, texopt_params *params)
{
    if (params->threads == 0 || (cfg->threads_per_job > 0 && params->threads > cfg->threads_per_job))
        params->threads = cfg->threads_per_job;
}

/* The files as stored and the resolved params: what a replay must repeat exactly. */
static int request_digest(const request_ctx *rq, const texopt_params *params, char out[17])
{
    cJSON *json = api_params_to_json(params);
    char *text = json ? cJSON_PrintUnformatted(json) : NULL;
    cJSON_Delete(json);
    if (!text)
        return -1;
    fingerprint_hex(fingerprint_mix(api_upload_digest(rq->upload), text, strlen(text)), out);
    free(text);
    return 0;
}

/* The job an Idempotency-Key names, or a 422 when the request differs from the one that made
 * it (jobs recorded before digests existed replay as before). */
static enum MHD_Result answer_known_key(request_ctx *rq, struct MHD_Connection *c, const job_record *existing,
                                        const char *digest)
{
    if (existing->request_digest[0] && strcmp(existing->request_digest, digest) != 0)
        return http_send_problem(rq, c, 422, "idempotency-key-reused", 0,
                                 "Idempotency-Key '%.128s' was used for job %s with other files or parameters; "
                                 "send a new key for a new request",
                                 existing->idempotency_key, existing->id);
    return send_job(rq, c, 202, existing, 1, 1);
}

static enum MHD_Result accept_job(request_ctx *rq, struct MHD_Connection *c, const texopt_params *params,
                                  const char *digest, uint64_t image_pixels)
{
    api_service *svc = rq->svc;
    job_record job;
    memset(&job, 0, sizeof job);
    memcpy(job.id, rq->job_id, sizeof job.id);
    job.created_ms = store_now_ms();
    job.eta_seconds = -1;
    job.params = *params;
    job.upload_bytes = api_upload_file_bytes(rq->upload);
    job.image_pixels = image_pixels;
    snprintf(job.model_name, sizeof job.model_name, "%s", api_upload_model_name(rq->upload));
    snprintf(job.input_rel, sizeof job.input_rel, "%s", api_upload_model_rel(rq->upload));
    const char *key = MHD_lookup_connection_value(c, MHD_HEADER_KIND, "Idempotency-Key");
    snprintf(job.idempotency_key, sizeof job.idempotency_key, "%s", key ? key : "");
    snprintf(job.request_digest, sizeof job.request_digest, "%s", digest);

    job_record existing;
    int rc = store_add(svc->store, &job, &existing);
    if (rc == STORE_DUPLICATE)
        return answer_known_key(rq, c, &existing, digest); /* a concurrent request won the race */
    if (rc != STORE_OK && store_unreachable(svc->store))
        return http_store_unreachable(rq, c);
    if (rc != STORE_OK)
        return storage_full(rq, c, "the job cannot be recorded now (the disk is full)");
    rq->job_accepted = 1;
    /* A shared store's workers lease the job from the database, on any node. */
    int pushed = store_shared(svc->store) ? QUEUE_OK : queue_push(svc->queue, job.id, 0);
    if (pushed != QUEUE_OK) {
        job_record gone;
        store_cancel(svc->store, job.id, &gone);
        store_delete(svc->store, job.id);
        if (pushed == QUEUE_FULL)
            return http_send_problem(rq, c, 503, "queue-full", QUEUE_FULL_RETRY_SECONDS,
                                     "the job queue is full; retry later");
        return http_send_problem(rq, c, 503, "shutting-down", 5, "the service is shutting down; retry shortly");
    }
    store_get(svc->store, job.id, &job);
    return send_job(rq, c, 202, &job, 1, 0);
}

enum MHD_Result jobs_post_complete(request_ctx *rq, struct MHD_Connection *c)
{
    if (!rq->upload)
        return http_send_problem(rq, c, 500, "internal-error", 0, "upload state lost");
    const char *slug, *detail;
    if (api_upload_finish(rq->upload) != 0) {
        int status = api_upload_error(rq->upload, &slug, &detail);
        return http_send_problem(rq, c, status, slug, status == 503 ? STORAGE_RETRY_SECONDS : 0, "%s", detail);
    }
    char err[512] = "";
    texopt_params params;
    if (read_params(rq, c, &params, err, sizeof err) != TEXOPT_OK)
        return http_send_problem(rq, c, 400, "invalid-params", 0, "%s", err);
    apply_thread_policy(&rq->svc->config, &params);
    char digest[17];
    if (request_digest(rq, &params, digest) != 0)
        return http_send_problem(rq, c, 500, "out-of-memory", 0, "out of memory");
    const char *key = MHD_lookup_connection_value(c, MHD_HEADER_KIND, "Idempotency-Key");
    job_record existing;
    if (rq->key_known && store_find_key(rq->svc->store, key, &existing) == STORE_OK)
        return answer_known_key(rq, c, &existing, digest);

    char model[PATH_MAX];
    snprintf(model, sizeof model, "%s/%s", rq->job_dir, api_upload_model_rel(rq->upload));
    uint64_t pixels = 0;
    texopt_status s =
        api_model_check(model, rq->svc->config.max_upload_bytes, rq->svc->config.max_pixels, &pixels, err, sizeof err);
    if (s != TEXOPT_OK) {
        int status = api_status_from_engine(s);
        return http_send_problem(rq, c, status, api_slug_from_engine(s), 0, "%s", err[0] ? err : texopt_strerror(s));
    }
    return accept_job(rq, c, &params, digest, pixels);
}

void jobs_post_abandon(request_ctx *rq)
{
    if (rq->job_id[0] && !rq->job_accepted)
        fs_remove_tree(rq->job_dir);
}

/* ---- GET /v1/jobs, GET/DELETE /v1/jobs/{id} ------------------------------------------- */

#define LIST_MAX 100

enum MHD_Result jobs_list(request_ctx *rq, struct MHD_Connection *c)
{
    const char *limit_text = MHD_lookup_connection_value(c, MHD_GET_ARGUMENT_KIND, "limit");
    const char *after = MHD_lookup_connection_value(c, MHD_GET_ARGUMENT_KIND, "after");
    char *end = NULL;
    long limit = limit_text ? strtol(limit_text, &end, 10) : 20;
    if (limit_text && (*end || limit < 1 || limit > LIST_MAX))
        return http_send_problem(rq, c, 400, "bad-query", 0, "limit must be an integer in 1 .. %d", LIST_MAX);
    job_record probe;
    if (after && store_get(rq->svc->store, after, &probe) != STORE_OK)
        return http_send_problem(rq, c, 400, "bad-query", 0, "after: no job '%.40s'", after);
    job_record *page = malloc(sizeof *page * (size_t)limit);
    if (!page)
        return MHD_NO;
    int more = 0;
    int n = store_list(rq->svc->store, after, page, (int)limit, &more);
    cJSON *o = cJSON_CreateObject();
    cJSON *items = cJSON_AddArrayToObject(o, "jobs");
    for (int i = 0; i < n; i++)
        cJSON_AddItemToArray(items, api_job_to_json(&page[i]));
    if (more && n > 0) {
        char next[128];
        snprintf(next, sizeof next, "/v1/jobs?limit=%ld&after=%s", limit, page[n - 1].id);
        cJSON_AddStringToObject(o, "next", next);
    } else {
        cJSON_AddNullToObject(o, "next");
    }
    free(page);
    char *body = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    if (!body)
        return MHD_NO;
    enum MHD_Result ok = http_send_text(rq, c, 200, "application/json", body, strlen(body));
    free(body);
    return ok;
}

static enum MHD_Result no_such_job(request_ctx *rq, struct MHD_Connection *c)
{
    return http_send_problem(rq, c, 404, "job-not-found", 0, "no job %s (never created, or deleted)", rq->match.id);
}

enum MHD_Result jobs_get(request_ctx *rq, struct MHD_Connection *c)
{
    job_record job;
    int rc = store_get(rq->svc->store, rq->match.id, &job);
    if (rc == STORE_IO)
        return http_store_unreachable(rq, c);
    if (rc != STORE_OK)
        return no_such_job(rq, c);
    return send_job(rq, c, 200, &job, 0, 0);
}

enum MHD_Result jobs_delete(request_ctx *rq, struct MHD_Connection *c)
{
    job_record job;
    switch (store_cancel(rq->svc->store, rq->match.id, &job)) {
    case CANCEL_NOT_FOUND: return no_such_job(rq, c);
    case CANCEL_DONE: queue_remove(rq->svc->queue, job.id); return send_job(rq, c, 200, &job, 0, 0);
    case CANCEL_REQUESTED: return send_job(rq, c, 202, &job, 0, 0);
    case CANCEL_UNSAVED:
        if (store_unreachable(rq->svc->store))
            return http_store_unreachable(rq, c);
        return storage_full(rq, c, "the cancel cannot be recorded now (the disk is full); the job stays queued");
    case CANCEL_FINISHED: break;
    }
    int rc = store_delete(rq->svc->store, rq->match.id);
    if (rc == STORE_NOT_FOUND)
        return no_such_job(rq, c);
    if (rc == STORE_CONFLICT)
        return http_send_problem(rq, c, 409, "job-busy", POLL_RETRY_SECONDS, "job %s is not finished", job.id);
    struct MHD_Response *r = MHD_create_response_from_buffer(0, (void *)"", MHD_RESPMEM_PERSISTENT);
    return http_send(rq, c, 204, r);
}

/* ---- the job's files ---------------------------------------------------------------- */

/* A file name safe inside a quoted Content-Disposition value: the model's stem. */
static void download_name(const char *model_name, char *out, size_t out_len)
{
    char stem[200];
    size_t n = 0;
    for (const char *p = model_name; *p && n + 1 < sizeof stem; p++) {
        char ch = *p;
        int ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '-' ||
                 ch == '_' || ch == '.';
        stem[n++] = ok ? ch : '_';
    }
    stem[n] = '\0';
    char *dot = strrchr(stem, '.');
    if (dot && dot != stem)
        *dot = '\0';
    snprintf(out, out_len, "attachment; filename=\"%s-texopt.glb\"", n ? stem : "model");
}

static enum MHD_Result send_file(request_ctx *rq, struct MHD_Connection *c, const char *path, const char *content_type,
                                 const char *disposition)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0) {
        if (fd >= 0)
            close(fd);
        return http_send_problem(rq, c, 500, "storage-error", 0, "cannot read the job's file: %s", strerror(errno));
    }
    /* From the descriptor: libmicrohttpd sends it (sendfile where it can) and closes it. */
    struct MHD_Response *r = MHD_create_response_from_fd((uint64_t)st.st_size, fd);
    if (!r) {
        close(fd);
        return MHD_NO;
    }
    MHD_add_response_header(r, "Content-Type", content_type);
    if (disposition)
        MHD_add_response_header(r, "Content-Disposition", disposition);
    return http_send(rq, c, 200, r);
}

enum MHD_Result jobs_file(request_ctx *rq, struct MHD_Connection *c)
{
    job_record job;
    int rc = store_get(rq->svc->store, rq->match.id, &job);
    if (rc == STORE_IO)
        return http_store_unreachable(rq, c);
    if (rc != STORE_OK)
        return no_such_job(rq, c);
    char dir[PATH_MAX - 32], path[PATH_MAX];
    store_job_dir(rq->svc->store, job.id, dir, sizeof dir);
    if (rq->match.route == ROUTE_JOB_REPORT) {
        snprintf(path, sizeof path, "%s/report.html", dir);
        if (job.state != JOB_SUCCEEDED || access(path, R_OK) != 0)
            return http_send_problem(rq, c, 404, "no-report", 0,
                                     "job %s has no report: a report is written for jobs created with "
                                     "evaluate=true, once they succeeded",
                                     job.id);
        return send_file(rq, c, path, "text/html; charset=utf-8", NULL);
    }
    if (!job_state_finished(job.state))
        return http_send_problem(rq, c, 409, "job-not-finished", POLL_RETRY_SECONDS,
                                 "job %s is %s; its outputs exist once it succeeded", job.id,
                                 job_state_name(job.state));
    if (job.state != JOB_SUCCEEDED)
        return http_send_problem(rq, c, 409, "job-not-succeeded", 0, "job %s %s and has no outputs", job.id,
                                 job_state_name(job.state));
    if (rq->match.route == ROUTE_JOB_STATS) {
        snprintf(path, sizeof path, "%s/stats.json", dir);
        return send_file(rq, c, path, "application/json", NULL);
    }
    char disposition[260];
    download_name(job.model_name, disposition, sizeof disposition);
    snprintf(path, sizeof path, "%s/result.glb", dir);
    return send_file(rq, c, path, "model/gltf-binary", disposition);
}
