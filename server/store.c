/* store.c - jobs in memory and on disk (see the DESIGN comment in store.h). */
#define _DEFAULT_SOURCE
#include "store.h"

#include <cjson/cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <time.h>
#include <unistd.h>

#include "fsutil.h"
#include "log.h"
#include "params_json.h"
#include "store_backend.h"
#include "texopt.h"

/* A run's end that could not be written yet: the job stays "running" (what job.json says)
 * until store_retry_unsaved writes it. */
typedef struct unsaved_end {
    int pending;
    job_state state;
    job_problem problem;
    int has_report;
    int64_t finished_ms;
} unsaved_end;

struct store_job {
    job_record rec;
    atomic_int cancel;
    int64_t published_ms;
    double published_progress;
    unsaved_end unsaved;
};

/* The on-disk store; base comes first, so a job_store * of this store is a disk_store *. */
typedef struct disk_store {
    job_store base;
    pthread_mutex_t mu;
    pthread_cond_t changed;
    pthread_mutex_t persist_mu; /* orders job.json writes; never taken while holding mu */
    char jobs_dir[2048];
    store_job **jobs; /* creation order: oldest first */
    int count, capacity;
    int closing;
    atomic_int unsaved; /* jobs whose end is not on disk yet */
} disk_store;

/* Event ids of a job's run n + 1 after a crash start at (n + 1) * EVENT_ID_EPOCH. */
#define EVENT_ID_EPOCH 1000000000LL

static const char *const state_names[JOB_STATE_COUNT] = {"queued", "running", "succeeded", "failed", "canceled"};

const char *job_state_name(job_state state)
{
    return (unsigned)state < JOB_STATE_COUNT ? state_names[state] : "unknown";
}

int job_state_finished(job_state state)
{
    return state == JOB_SUCCEEDED || state == JOB_FAILED || state == JOB_CANCELED;
}

void job_problem_add_json(struct cJSON *parent, const job_problem *problem)
{
    cJSON *p = cJSON_AddObjectToObject(parent, "problem");
    cJSON_AddStringToObject(p, "type", problem->type);
    cJSON_AddStringToObject(p, "title", problem->title);
    cJSON_AddNumberToObject(p, "status", problem->status);
    cJSON_AddStringToObject(p, "detail", problem->detail);
}

int64_t store_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

static void disk_job_dir(const job_store *base, const char *id, char *dir, size_t dir_len)
{
    const disk_store *store = (const disk_store *)base;
    snprintf(dir, dir_len, "%s/%s", store->jobs_dir, id);
}

/* ---- job.json ---------------------------------------------------------------------- */

char *store_record_to_json(const job_record *r)
{
    cJSON *o = cJSON_CreateObject();
    if (!o)
        return NULL;
    cJSON_AddNumberToObject(o, "version", 1);
    cJSON_AddStringToObject(o, "id", r->id);
    cJSON_AddStringToObject(o, "state", job_state_name(r->state));
    cJSON_AddNumberToObject(o, "created_ms", (double)r->created_ms);
    cJSON_AddNumberToObject(o, "started_ms", (double)r->started_ms);
    cJSON_AddNumberToObject(o, "finished_ms", (double)r->finished_ms);
    cJSON_AddNumberToObject(o, "attempts", r->attempts);
    cJSON_AddStringToObject(o, "stage", r->stage);
    cJSON_AddNumberToObject(o, "progress", r->progress);
    cJSON_AddNumberToObject(o, "event_seq", (double)r->event_seq);
    cJSON_AddStringToObject(o, "model_name", r->model_name);
    cJSON_AddStringToObject(o, "input", r->input_rel);
    cJSON_AddStringToObject(o, "idempotency_key", r->idempotency_key);
    cJSON_AddStringToObject(o, "request_digest", r->request_digest);
    cJSON_AddNumberToObject(o, "upload_bytes", (double)r->upload_bytes);
    cJSON_AddBoolToObject(o, "report", r->has_report != 0);
    cJSON_AddNumberToObject(o, "image_pixels", (double)r->image_pixels);
    cJSON_AddItemToObject(o, "params", api_params_to_json(&r->params));
    if (r->state == JOB_FAILED)
        job_problem_add_json(o, &r->problem);
    char *text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    return text;
}

static void copy_string(char *dst, size_t dst_len, const cJSON *obj, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    snprintf(dst, dst_len, "%s", cJSON_IsString(v) ? v->valuestring : "");
}

static double get_double(const cJSON *obj, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    return cJSON_IsNumber(v) ? v->valuedouble : 0;
}

int store_record_from_json(const char *text, job_record *r, char *err, size_t err_len)
{
    cJSON *o = cJSON_Parse(text);
    if (!o)
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "not JSON"), -1;
    memset(r, 0, sizeof *r);
    copy_string(r->id, sizeof r->id, o, "id");
    char state[16];
    copy_string(state, sizeof state, o, "state");
    r->state = JOB_STATE_COUNT;
    for (int s = 0; s < JOB_STATE_COUNT; s++)
        if (strcmp(state, state_names[s]) == 0)
            r->state = (job_state)s;
    r->created_ms = (int64_t)get_double(o, "created_ms");
    r->started_ms = (int64_t)get_double(o, "started_ms");
    r->finished_ms = (int64_t)get_double(o, "finished_ms");
    r->attempts = (int)get_double(o, "attempts");
    r->event_seq = (long long)get_double(o, "event_seq");
    r->progress = get_double(o, "progress");
    copy_string(r->stage, sizeof r->stage, o, "stage");
    r->upload_bytes = (uint64_t)get_double(o, "upload_bytes");
    r->has_report = cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(o, "report"));
    r->image_pixels = (uint64_t)get_double(o, "image_pixels");
    r->eta_seconds = -1;
    copy_string(r->model_name, sizeof r->model_name, o, "model_name");
    copy_string(r->input_rel, sizeof r->input_rel, o, "input");
    copy_string(r->idempotency_key, sizeof r->idempotency_key, o, "idempotency_key");
    copy_string(r->request_digest, sizeof r->request_digest, o, "request_digest");
    const cJSON *problem = cJSON_GetObjectItemCaseSensitive(o, "problem");
    if (problem) {
        r->problem.status = (int)get_double(problem, "status");
        copy_string(r->problem.type, sizeof r->problem.type, problem, "type");
        copy_string(r->problem.title, sizeof r->problem.title, problem, "title");
        copy_string(r->problem.detail, sizeof r->problem.detail, problem, "detail");
    }
    texopt_status s = api_params_from_json(cJSON_GetObjectItemCaseSensitive(o, "params"), &r->params, err, err_len);
    cJSON_Delete(o);
    if (s != TEXOPT_OK)
        return -1;
    if (r->state == JOB_STATE_COUNT || strlen(r->id) != JOB_ID_LEN || !r->input_rel[0])
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "missing id, state or input"), -1;
    return 0;
}

/* Writes record as its job's job.json. The caller holds persist_mu, which orders the writes
 * (an older record never overwrites a newer), keeps store_delete from freeing the job and
 * every other state change from starting meanwhile. Written outside mu: the fsync must not
 * stall readers. */
static int persist_record(disk_store *store, const job_record *record)
{
    int rc = -1;
    char *text = store_record_to_json(record);
    if (text) {
        char path[PATH_MAX];
        snprintf(path, sizeof path, "%s/%s/job.json", store->jobs_dir, record->id);
        rc = fs_write_atomic(path, text, strlen(text));
        if (rc != 0) {
            char why[128];
            log_event("level=error event=persist job=%s state=%s error=%s", record->id, job_state_name(record->state),
                      log_quote(why, sizeof why, strerror(errno)));
        }
        free(text);
    }
    return rc;
}

/* Writes the job's current record (serialised under mu). */
static int persist_held(disk_store *store, store_job *job)
{
    pthread_mutex_lock(&store->mu);
    job_record copy = job->rec;
    pthread_mutex_unlock(&store->mu);
    return persist_record(store, &copy);
}

static void log_state(const job_record *r)
{
    char detail[600];
    if (r->state == JOB_FAILED)
        log_event("level=info event=job job=%s state=%s attempt=%d status=%d detail=%s", r->id,
                  job_state_name(r->state), r->attempts, r->problem.status,
                  log_quote(detail, sizeof detail, r->problem.detail));
    else
        log_event("level=info event=job job=%s state=%s attempt=%d", r->id, job_state_name(r->state), r->attempts);
}

/* ---- in-memory table (caller holds mu) ---------------------------------------------- */

static store_job *find(disk_store *store, const char *id)
{
    for (int i = 0; i < store->count; i++)
        if (strcmp(store->jobs[i]->rec.id, id) == 0)
            return store->jobs[i];
    return NULL;
}

static int append(disk_store *store, store_job *job)
{
    if (store->count == store->capacity) {
        int capacity = store->capacity ? store->capacity * 2 : 64;
        store_job **jobs = realloc(store->jobs, (size_t)capacity * sizeof *jobs);
        if (!jobs)
            return -1;
        store->jobs = jobs;
        store->capacity = capacity;
    }
    store->jobs[store->count++] = job;
    return 0;
}

static void remove_at(disk_store *store, int index)
{
    free(store->jobs[index]);
    memmove(&store->jobs[index], &store->jobs[index + 1], (size_t)(store->count - index - 1) * sizeof *store->jobs);
    store->count--;
}

/* A new event: everything watching this job wakes and sends the latest record. */
static void publish(disk_store *store, store_job *job)
{
    job->rec.event_seq++;
    job->published_ms = store_now_ms();
    job->published_progress = job->rec.progress;
    pthread_cond_broadcast(&store->changed);
}

/* ---- open / close ------------------------------------------------------------------ */

static int by_creation(const void *a, const void *b)
{
    const store_job *x = *(store_job *const *)a, *y = *(store_job *const *)b;
    if (x->rec.created_ms != y->rec.created_ms)
        return x->rec.created_ms < y->rec.created_ms ? -1 : 1;
    return strcmp(x->rec.id, y->rec.id);
}

static void load_one(disk_store *store, const char *name)
{
    char dir[PATH_MAX], path[PATH_MAX + 16], err[256] = "";
    snprintf(dir, sizeof dir, "%s/%s", store->jobs_dir, name);
    snprintf(path, sizeof path, "%s/job.json", dir);
    char *text = fs_read_small(path, 1 << 20, NULL);
    if (!text) {
        /* An upload cut off before it was accepted: nobody was promised this job. */
        log_event("level=info event=recover dir=%s action=remove reason=no-job-json", name);
        fs_remove_tree(dir);
        return;
    }
    store_job *job = calloc(1, sizeof *job);
    if (!job || store_record_from_json(text, &job->rec, err, sizeof err) != 0 || strcmp(job->rec.id, name) != 0) {
        char why[300];
        log_event("level=error event=recover dir=%s action=skip error=%s", name,
                  log_quote(why, sizeof why, err[0] ? err : "id does not match directory"));
        free(job);
        free(text);
        return;
    }
    free(text);
    int interrupted = job->rec.state == JOB_RUNNING;
    if (interrupted) {
        /* Progress events of the lost run were never written, so their ids are unknown
         * here: jump to a range no run reaches (one event per 250 ms at most), keeping the
         * ids a client saw smaller than every id it will see. */
        job->rec.event_seq = (long long)(job->rec.attempts + 1) * EVENT_ID_EPOCH;
        job->rec.state = JOB_QUEUED;
        job->rec.cancel_requested = 0;
        job->rec.progress = 0;
        job->rec.stage[0] = '\0';
    }
    if (append(store, job) != 0) {
        free(job);
        return;
    }
    if (interrupted) {
        log_event("level=info event=recover job=%s action=requeue reason=interrupted", name);
        persist_held(store, job);
    }
}

static const store_ops disk_ops;
static void disk_close(job_store *base);

job_store *store_open(const char *data_dir, char *err, size_t err_len)
{
    disk_store *store = calloc(1, sizeof *store);
    if (!store) {
        texopt_fail(err, err_len, TEXOPT_E_NOMEM, "out of memory");
        return NULL;
    }
    store->base.ops = &disk_ops;
    pthread_mutex_init(&store->mu, NULL);
    pthread_mutex_init(&store->persist_mu, NULL);
    pthread_cond_init(&store->changed, NULL);
    snprintf(store->jobs_dir, sizeof store->jobs_dir, "%s/jobs", data_dir);
    if (fs_mkdir_p(store->jobs_dir) != 0) {
        texopt_fail(err, err_len, TEXOPT_E_IO, "cannot create %s: %s", store->jobs_dir, strerror(errno));
        disk_close(&store->base);
        return NULL;
    }
    DIR *d = opendir(store->jobs_dir);
    if (!d) {
        texopt_fail(err, err_len, TEXOPT_E_IO, "cannot read %s: %s", store->jobs_dir, strerror(errno));
        disk_close(&store->base);
        return NULL;
    }
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        if (e->d_name[0] != '.')
            load_one(store, e->d_name);
    closedir(d);
    if (store->count > 1)
        qsort(store->jobs, (size_t)store->count, sizeof *store->jobs, by_creation);
    return &store->base;
}

static void disk_close(job_store *base)
{
    disk_store *store = (disk_store *)base;
    if (!store)
        return;
    for (int i = 0; i < store->count; i++)
        free(store->jobs[i]);
    free(store->jobs);
    pthread_mutex_destroy(&store->mu);
    pthread_mutex_destroy(&store->persist_mu);
    pthread_cond_destroy(&store->changed);
    free(store);
}

/* ---- jobs -------------------------------------------------------------------------- */

int store_random_id(char *id)
{
    unsigned char bytes[JOB_ID_LEN / 2];
    int fd = open("/dev/urandom", O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return -1;
    ssize_t n = read(fd, bytes, sizeof bytes);
    close(fd);
    if (n != (ssize_t)sizeof bytes)
        return -1;
    for (size_t i = 0; i < sizeof bytes; i++)
        snprintf(id + 2 * i, 3, "%02x", bytes[i]);
    return 0;
}

static void disk_run_dir(job_store *base, store_job *job, char *dir, size_t dir_len)
{
    disk_job_dir(base, job->rec.id, dir, dir_len);
}

static int disk_new_job_dir(job_store *base, char *id, char *dir, size_t dir_len)
{
    disk_store *store = (disk_store *)base;
    if (store_random_id(id) != 0)
        return -1;
    disk_job_dir(&store->base, id, dir, dir_len);
    return mkdir(dir, 0750);
}

static int disk_add(job_store *base, const job_record *record, job_record *existing)
{
    disk_store *store = (disk_store *)base;
    store_job *job = calloc(1, sizeof *job);
    if (!job)
        return STORE_IO;
    job->rec = *record;
    job->rec.state = JOB_QUEUED;
    job->rec.event_seq = 1;
    pthread_mutex_lock(&store->persist_mu);
    pthread_mutex_lock(&store->mu);
    if (record->idempotency_key[0]) {
        for (int i = 0; i < store->count; i++) {
            if (strcmp(store->jobs[i]->rec.idempotency_key, record->idempotency_key) == 0) {
                *existing = store->jobs[i]->rec;
                pthread_mutex_unlock(&store->mu);
                pthread_mutex_unlock(&store->persist_mu);
                free(job);
                return STORE_DUPLICATE;
            }
        }
    }
    int rc = append(store, job);
    pthread_mutex_unlock(&store->mu);
    if (rc != 0) {
        pthread_mutex_unlock(&store->persist_mu);
        free(job);
        return STORE_IO;
    }
    if (persist_held(store, job) != 0) {
        pthread_mutex_lock(&store->mu);
        for (int i = store->count - 1; i >= 0; i--)
            if (store->jobs[i] == job)
                remove_at(store, i);
        pthread_mutex_unlock(&store->mu);
        pthread_mutex_unlock(&store->persist_mu);
        return STORE_IO;
    }
    pthread_mutex_unlock(&store->persist_mu);
    log_state(record);
    return STORE_OK;
}

static int disk_get(job_store *base, const char *id, job_record *out)
{
    disk_store *store = (disk_store *)base;
    pthread_mutex_lock(&store->mu);
    store_job *job = find(store, id);
    if (job)
        *out = job->rec;
    pthread_mutex_unlock(&store->mu);
    return job ? STORE_OK : STORE_NOT_FOUND;
}

static int disk_find_key(job_store *base, const char *key, job_record *out)
{
    disk_store *store = (disk_store *)base;
    int rc = STORE_NOT_FOUND;
    pthread_mutex_lock(&store->mu);
    for (int i = 0; i < store->count && rc != STORE_OK; i++)
        if (strcmp(store->jobs[i]->rec.idempotency_key, key) == 0) {
            *out = store->jobs[i]->rec;
            rc = STORE_OK;
        }
    pthread_mutex_unlock(&store->mu);
    return rc;
}

static int disk_list(job_store *base, const char *after, job_record *out, int max, int *more)
{
    disk_store *store = (disk_store *)base;
    pthread_mutex_lock(&store->mu);
    int start = store->count - 1;
    if (after && *after) {
        start = -1;
        for (int i = store->count - 1; i >= 0; i--)
            if (strcmp(store->jobs[i]->rec.id, after) == 0)
                start = i - 1;
    }
    int n = 0;
    int i = start;
    for (; i >= 0 && n < max; i--)
        out[n++] = store->jobs[i]->rec;
    *more = i >= 0;
    pthread_mutex_unlock(&store->mu);
    return n;
}

static int disk_queued_ids(job_store *base, char (**ids)[JOB_ID_LEN + 1])
{
    disk_store *store = (disk_store *)base;
    pthread_mutex_lock(&store->mu);
    *ids = calloc((size_t)store->count + 1, sizeof **ids);
    int n = 0;
    for (int i = 0; *ids && i < store->count; i++)
        if (store->jobs[i]->rec.state == JOB_QUEUED)
            memcpy((*ids)[n++], store->jobs[i]->rec.id, JOB_ID_LEN + 1);
    pthread_mutex_unlock(&store->mu);
    return *ids ? n : -1;
}

static store_job *disk_begin(job_store *base, const char *id, job_record *out, const atomic_int **cancel)
{
    disk_store *store = (disk_store *)base;
    pthread_mutex_lock(&store->persist_mu);
    pthread_mutex_lock(&store->mu);
    store_job *job = find(store, id);
    if (!job || job->rec.state != JOB_QUEUED) {
        pthread_mutex_unlock(&store->mu);
        pthread_mutex_unlock(&store->persist_mu);
        return NULL;
    }
    job->rec.state = JOB_RUNNING;
    job->rec.attempts++;
    job->rec.started_ms = store_now_ms();
    job->rec.progress = 0;
    job->rec.stage[0] = '\0';
    job->rec.eta_seconds = -1;
    atomic_store(&job->cancel, 0);
    publish(store, job);
    *out = job->rec;
    *cancel = &job->cancel;
    pthread_mutex_unlock(&store->mu);
    persist_held(store, job);
    pthread_mutex_unlock(&store->persist_mu);
    log_state(out);
    return job;
}

static void disk_progress(job_store *base, store_job *job, const char *stage, double progress, double eta_seconds,
                          double mean_loss, double mean_area_scale)
{
    disk_store *store = (disk_store *)base;
    pthread_mutex_lock(&store->mu);
    int new_stage = strncmp(job->rec.stage, stage, sizeof job->rec.stage - 1) != 0;
    snprintf(job->rec.stage, sizeof job->rec.stage, "%s", stage);
    /* Within a run progress only grows: a client may draw it as a bar. */
    if (progress > job->rec.progress)
        job->rec.progress = progress > 1 ? 1 : progress;
    job->rec.eta_seconds = eta_seconds;
    job->rec.mean_loss = mean_loss;
    job->rec.mean_area_scale = mean_area_scale;
    if (store_progress_worth_publishing(new_stage, job->rec.progress, job->published_progress, store_now_ms(),
                                        job->published_ms))
        publish(store, job);
    pthread_mutex_unlock(&store->mu);
}

static void apply_end(job_record *r, const unsaved_end *end)
{
    r->state = end->state;
    r->has_report = end->has_report;
    if (end->state == JOB_SUCCEEDED)
        r->progress = 1;
    if (job_state_finished(end->state))
        r->finished_ms = end->finished_ms;
    if (end->state == JOB_FAILED)
        r->problem = end->problem;
    r->eta_seconds = end->state == JOB_SUCCEEDED ? 0 : -1;
    r->cancel_requested = 0;
    if (end->state == JOB_QUEUED) { /* re-queued at shutdown: the re-run starts from nothing */
        r->progress = 0;
        r->stage[0] = '\0';
    }
}

/* Writes the job's end, then makes it what everyone sees; while it cannot be written the job
 * stays running (as job.json says) and the end waits in job->unsaved. Holds persist_mu. */
static int save_end(disk_store *store, store_job *job)
{
    pthread_mutex_lock(&store->mu);
    job_record next = job->rec;
    apply_end(&next, &job->unsaved);
    next.event_seq++;
    pthread_mutex_unlock(&store->mu);
    if (persist_record(store, &next) != 0)
        return STORE_IO;
    pthread_mutex_lock(&store->mu);
    apply_end(&job->rec, &job->unsaved);
    job->unsaved.pending = 0;
    publish(store, job);
    pthread_mutex_unlock(&store->mu);
    log_state(&next);
    return STORE_OK;
}

static int end_run(disk_store *store, store_job *job, job_state state, const job_problem *problem, int has_report)
{
    pthread_mutex_lock(&store->persist_mu);
    unsaved_end *end = &job->unsaved;
    memset(end, 0, sizeof *end);
    end->pending = 1;
    end->state = state;
    if (problem)
        end->problem = *problem;
    end->has_report = has_report;
    end->finished_ms = store_now_ms();
    int rc = save_end(store, job);
    if (rc != STORE_OK)
        atomic_fetch_add(&store->unsaved, 1);
    pthread_mutex_unlock(&store->persist_mu);
    return rc;
}

static int disk_finish(job_store *base, store_job *job, job_state state, const job_problem *problem, int has_report)
{
    disk_store *store = (disk_store *)base;
    return end_run(store, job, state, problem, has_report);
}

static int disk_requeue(job_store *base, store_job *job)
{
    disk_store *store = (disk_store *)base;
    return end_run(store, job, JOB_QUEUED, NULL, 0);
}

static int disk_retry_unsaved(job_store *base)
{
    disk_store *store = (disk_store *)base;
    if (atomic_load(&store->unsaved) == 0)
        return 0;
    /* persist_mu keeps every job in place: adding and deleting take it too. */
    pthread_mutex_lock(&store->persist_mu);
    for (int i = 0; i < store->count; i++) {
        store_job *job = store->jobs[i];
        if (job->unsaved.pending && save_end(store, job) == STORE_OK)
            atomic_fetch_sub(&store->unsaved, 1);
    }
    pthread_mutex_unlock(&store->persist_mu);
    return atomic_load(&store->unsaved);
}

static cancel_outcome disk_cancel(job_store *base, const char *id, job_record *out)
{
    disk_store *store = (disk_store *)base;
    pthread_mutex_lock(&store->persist_mu);
    pthread_mutex_lock(&store->mu);
    store_job *job = find(store, id);
    cancel_outcome outcome = CANCEL_NOT_FOUND;
    if (job && job->rec.state == JOB_QUEUED) {
        /* Written first: a cancel that is not on disk would be undone by a restart. No
         * other state change runs meanwhile (they all take persist_mu). */
        job_record next = job->rec;
        next.state = JOB_CANCELED;
        next.finished_ms = store_now_ms();
        next.event_seq++;
        pthread_mutex_unlock(&store->mu);
        int saved = persist_record(store, &next) == 0;
        pthread_mutex_lock(&store->mu);
        if (saved) {
            job->rec.state = JOB_CANCELED;
            job->rec.finished_ms = next.finished_ms;
            publish(store, job);
        }
        outcome = saved ? CANCEL_DONE : CANCEL_UNSAVED;
    } else if (job && job->rec.state == JOB_RUNNING) {
        atomic_store(&job->cancel, 1);
        job->rec.cancel_requested = 1;
        publish(store, job);
        outcome = CANCEL_REQUESTED;
    } else if (job) {
        outcome = CANCEL_FINISHED;
    }
    if (job)
        *out = job->rec;
    pthread_mutex_unlock(&store->mu);
    pthread_mutex_unlock(&store->persist_mu);
    if (outcome == CANCEL_DONE)
        log_state(out);
    return outcome;
}

static void disk_cancel_running(job_store *base)
{
    disk_store *store = (disk_store *)base;
    pthread_mutex_lock(&store->mu);
    for (int i = 0; i < store->count; i++)
        if (store->jobs[i]->rec.state == JOB_RUNNING)
            atomic_store(&store->jobs[i]->cancel, 1);
    pthread_mutex_unlock(&store->mu);
}

static int delete_locked(disk_store *store, int index)
{
    char dir[PATH_MAX];
    disk_job_dir(&store->base, store->jobs[index]->rec.id, dir, sizeof dir);
    log_event("level=info event=job job=%s state=deleted", store->jobs[index]->rec.id);
    remove_at(store, index);
    pthread_cond_broadcast(&store->changed);
    return fs_remove_tree(dir);
}

static int disk_delete(job_store *base, const char *id)
{
    disk_store *store = (disk_store *)base;
    /* persist_mu first: a job.json write of this job may not be under way while its
     * directory goes away. */
    pthread_mutex_lock(&store->persist_mu);
    pthread_mutex_lock(&store->mu);
    int rc = STORE_NOT_FOUND;
    for (int i = 0; i < store->count; i++) {
        if (strcmp(store->jobs[i]->rec.id, id) != 0)
            continue;
        rc = job_state_finished(store->jobs[i]->rec.state) ? STORE_OK : STORE_CONFLICT;
        if (rc == STORE_OK && delete_locked(store, i) != 0)
            rc = STORE_IO;
        break;
    }
    pthread_mutex_unlock(&store->mu);
    pthread_mutex_unlock(&store->persist_mu);
    return rc;
}

static int disk_expire(job_store *base, int64_t now_ms, int64_t retention_ms)
{
    disk_store *store = (disk_store *)base;
    pthread_mutex_lock(&store->persist_mu);
    pthread_mutex_lock(&store->mu);
    int n = 0;
    for (int i = store->count - 1; i >= 0; i--) {
        const job_record *r = &store->jobs[i]->rec;
        if (job_state_finished(r->state) && r->finished_ms + retention_ms < now_ms) {
            delete_locked(store, i);
            n++;
        }
    }
    pthread_mutex_unlock(&store->mu);
    pthread_mutex_unlock(&store->persist_mu);
    return n;
}

static int disk_wait_event(job_store *base, const char *id, long long after_seq, int timeout_ms, job_record *out)
{
    disk_store *store = (disk_store *)base;
    struct timespec deadline;
    clock_gettime(CLOCK_REALTIME, &deadline);
    deadline.tv_sec += timeout_ms / 1000;
    deadline.tv_nsec += (long)(timeout_ms % 1000) * 1000000L;
    if (deadline.tv_nsec >= 1000000000L) {
        deadline.tv_sec++;
        deadline.tv_nsec -= 1000000000L;
    }
    pthread_mutex_lock(&store->mu);
    int rc;
    for (;;) {
        store_job *job = find(store, id);
        if (store->closing) {
            rc = -4;
            break;
        }
        if (!job) {
            rc = STORE_NOT_FOUND;
            break;
        }
        *out = job->rec;
        /* An id from the future (a data directory restored from elsewhere): the client's
         * view is stale whatever it says, so it gets the current state at once. */
        if (job->rec.event_seq != after_seq) {
            rc = 1;
            break;
        }
        if (pthread_cond_timedwait(&store->changed, &store->mu, &deadline) == ETIMEDOUT) {
            job = find(store, id);
            if (job)
                *out = job->rec;
            rc = job ? 0 : STORE_NOT_FOUND;
            break;
        }
    }
    pthread_mutex_unlock(&store->mu);
    return rc;
}

static void disk_wake_all(job_store *base)
{
    disk_store *store = (disk_store *)base;
    pthread_mutex_lock(&store->mu);
    store->closing = 1;
    pthread_cond_broadcast(&store->changed);
    pthread_mutex_unlock(&store->mu);
}

/* Room kept free for job records, beyond an upload's own bytes. */
#define STORE_RESERVE_BYTES (1ull << 20)

static int disk_can_store(job_store *base, uint64_t bytes)
{
    disk_store *store = (disk_store *)base;
    return atomic_load(&store->unsaved) == 0 && store_dir_has_room(store->jobs_dir, bytes);
}

int store_dir_has_room(const char *dir, uint64_t bytes)
{
    struct statvfs fs;
    if (statvfs(dir, &fs) != 0)
        return 0;
    uint64_t free_bytes = (uint64_t)fs.f_bavail * (uint64_t)fs.f_frsize;
    return free_bytes >= bytes + STORE_RESERVE_BYTES;
}

static void disk_counts(job_store *base, int counts[JOB_STATE_COUNT])
{
    disk_store *store = (disk_store *)base;
    memset(counts, 0, sizeof(int) * JOB_STATE_COUNT);
    pthread_mutex_lock(&store->mu);
    for (int i = 0; i < store->count; i++)
        counts[store->jobs[i]->rec.state]++;
    pthread_mutex_unlock(&store->mu);
}

int store_progress_worth_publishing(int new_stage, double progress, double published_progress, int64_t now_ms,
                                    int64_t published_ms)
{
    return new_stage || progress >= published_progress + 0.005 || now_ms >= published_ms + 250;
}

static const store_ops disk_ops = {
    .name = "disk",
    .close = disk_close,
    .new_job_dir = disk_new_job_dir,
    .job_dir = disk_job_dir,
    .run_dir = disk_run_dir,
    .add = disk_add,
    .get = disk_get,
    .find_key = disk_find_key,
    .list = disk_list,
    .queued_ids = disk_queued_ids,
    .begin = disk_begin,
    .progress = disk_progress,
    .finish = disk_finish,
    .requeue = disk_requeue,
    .retry_unsaved = disk_retry_unsaved,
    .can_store = disk_can_store,
    .cancel = disk_cancel,
    .cancel_running = disk_cancel_running,
    .delete_job = disk_delete,
    .expire = disk_expire,
    .wait_event = disk_wait_event,
    .wake_all = disk_wake_all,
    .counts = disk_counts,
};
