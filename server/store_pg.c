/* store_pg.c - the job store in PostgreSQL (see the DESIGN comment in store_pg.h). */
#define _DEFAULT_SOURCE
#include "store_pg.h"

#include <dirent.h>
#include <errno.h>
#include <libpq-fe.h>
#include <limits.h>
#include <poll.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "fsutil.h"
#include "log.h"
#include "store_backend.h"
#include "store_lease.h"
#include "store_pg_schema.h"
#include "store_url.h"
#include "texopt.h"

/* Connections for requests and workers; a caller past this many waits for one. */
#define POOL_SIZE 16
/* Any wait for a notification also ends after this long (a lost one only delays). */
#define WAKE_MS 1000
/* A job directory without a row this old is an upload its node died in (a job's directory
 * exists before its row is committed); far longer than any upload may take. */
#define ORPHAN_AGE_SECONDS (24 * 3600)
/* Key of the advisory lock that serialises schema migrations across nodes. */
#define SCHEMA_LOCK_KEY "4407202611"

/* The database's clock in Unix ms: every lease is measured on one clock. */
#define NOW_MS "(extract(epoch from clock_timestamp()) * 1000)::bigint"
#define COLS                                                                                                           \
    "id, description, state, attempts, event_seq, stage, progress, eta_seconds, mean_loss, mean_area_scale, "          \
    "started_ms, finished_ms, cancel_requested, has_report, problem_status, problem_type, problem_title, "             \
    "problem_detail"
#define FINISHED "('succeeded', 'failed', 'canceled')"

/* A job this node runs. */
typedef struct pg_job {
    char id[JOB_ID_LEN + 1];
    atomic_int cancel;
    int64_t leased_ms; /* this node's clock, for lease_lost */
    char stage[16];
    double progress, published_progress;
    int64_t published_ms;
    char run_dir[PATH_MAX];
    struct pg_job *next;
} pg_job;

typedef struct pg_store {
    job_store base;
    char conninfo[1024];
    char node[128];
    char jobs_dir[1040];
    int lease_seconds, max_attempts;
    pthread_mutex_t mu; /* the pool, the running list, the wake counters, closing */
    pthread_cond_t pool_free, queue_changed, events_changed;
    PGconn *pool[POOL_SIZE];
    int pool_busy[POOL_SIZE];
    pg_job *running;
    unsigned long queue_gen, events_gen;
    int closing;
    atomic_int unreachable;
    pthread_t node_thread;
    int node_thread_started;
} pg_store;

static pg_store *as_pg(job_store *base)
{
    return (pg_store *)base;
}

/* ---- connections -------------------------------------------------------------------- */

static PGconn *connect_db(const char *conninfo)
{
    const char *keys[] = {"dbname", "connect_timeout", "application_name", "options", NULL};
    const char *values[] = {conninfo, "3", "texoptd", "-c client_min_messages=warning", NULL};
    PGconn *conn = PQconnectdbParams(keys, values, 1);
    if (conn && PQstatus(conn) == CONNECTION_OK)
        return conn;
    PQfinish(conn);
    return NULL;
}

/* A connection of the pool (connecting one when needed), or NULL when the database cannot
 * be reached. Give it back with give_back. */
static PGconn *borrow(pg_store *s, int *slot)
{
    pthread_mutex_lock(&s->mu);
    int pick = -1;
    for (;;) {
        for (int i = 0; i < POOL_SIZE && pick < 0; i++)
            if (!s->pool_busy[i] && s->pool[i])
                pick = i;
        for (int i = 0; i < POOL_SIZE && pick < 0; i++)
            if (!s->pool_busy[i])
                pick = i;
        if (pick >= 0)
            break;
        pthread_cond_wait(&s->pool_free, &s->mu);
    }
    s->pool_busy[pick] = 1;
    PGconn *conn = s->pool[pick];
    pthread_mutex_unlock(&s->mu);
    if (!conn) {
        conn = connect_db(s->conninfo);
        if (!conn) {
            atomic_store(&s->unreachable, 1);
            pthread_mutex_lock(&s->mu);
            s->pool_busy[pick] = 0;
            pthread_cond_signal(&s->pool_free);
            pthread_mutex_unlock(&s->mu);
            return NULL;
        }
    }
    *slot = pick;
    return conn;
}

static void give_back(pg_store *s, int slot, PGconn *conn)
{
    if (conn && (PQstatus(conn) != CONNECTION_OK || PQtransactionStatus(conn) != PQTRANS_IDLE)) {
        PQfinish(conn);
        conn = NULL;
    }
    pthread_mutex_lock(&s->mu);
    s->pool[slot] = conn;
    s->pool_busy[slot] = 0;
    pthread_cond_signal(&s->pool_free);
    pthread_mutex_unlock(&s->mu);
}

/* Runs sql with text parameters on *conn; the result when it succeeded, else NULL (logged).
 * A pooled connection may have died with the server it knew (a restart): outside a
 * transaction the statement is sent again once on a new connection, which replaces *conn
 * (NULL when none can be made). */
static PGresult *exec_on(pg_store *s, PGconn **conn, const char *sql, int n, const char *const *params)
{
    for (int attempt = 0;; attempt++) {
        int idle = PQtransactionStatus(*conn) == PQTRANS_IDLE;
        PGresult *res = PQexecParams(*conn, sql, n, NULL, params, NULL, NULL, 0);
        ExecStatusType st = PQresultStatus(res);
        if (st == PGRES_COMMAND_OK || st == PGRES_TUPLES_OK)
            return res;
        PQclear(res);
        int broken = PQstatus(*conn) != CONNECTION_OK;
        if (broken && idle && attempt == 0) {
            PQfinish(*conn);
            if ((*conn = connect_db(s->conninfo)) != NULL)
                continue;
        }
        char quoted[400];
        log_event("level=error event=database error=%s",
                  log_quote(quoted, sizeof quoted, *conn ? PQerrorMessage(*conn) : "cannot connect"));
        if (broken)
            atomic_store(&s->unreachable, 1);
        return NULL;
    }
}

/* exec_on with a connection of the pool. */
static PGresult *exec_sql(pg_store *s, const char *sql, int n, const char *const *params)
{
    int slot;
    PGconn *conn = borrow(s, &slot);
    if (!conn)
        return NULL;
    PGresult *res = exec_on(s, &conn, sql, n, params);
    give_back(s, slot, conn);
    return res;
}

/* ---- rows ---------------------------------------------------------------------------- */

static job_state state_from_name(const char *name)
{
    for (int st = 0; st < JOB_STATE_COUNT; st++)
        if (strcmp(name, job_state_name((job_state)st)) == 0)
            return (job_state)st;
    return JOB_FAILED;
}

/* Row `row` of res, columns COLS from column `col`, as a record. */
static int row_to_record(const PGresult *res, int row, int col, job_record *out)
{
#define V(k) PQgetvalue(res, row, col + (k))
    char err[256];
    if (store_record_from_json(V(1), out, err, sizeof err) != 0) {
        log_event("level=error event=database job=%s error=\"unreadable description\"", V(0));
        return -1;
    }
    out->state = state_from_name(V(2));
    out->attempts = atoi(V(3));
    out->event_seq = atoll(V(4));
    snprintf(out->stage, sizeof out->stage, "%s", V(5));
    out->progress = atof(V(6));
    out->eta_seconds = atof(V(7));
    out->mean_loss = atof(V(8));
    out->mean_area_scale = atof(V(9));
    out->started_ms = atoll(V(10));
    out->finished_ms = atoll(V(11));
    out->cancel_requested = V(12)[0] == 't';
    out->has_report = V(13)[0] == 't';
    memset(&out->problem, 0, sizeof out->problem);
    if (out->state == JOB_FAILED) {
        out->problem.status = atoi(V(14));
        snprintf(out->problem.type, sizeof out->problem.type, "%s", V(15));
        snprintf(out->problem.title, sizeof out->problem.title, "%s", V(16));
        snprintf(out->problem.detail, sizeof out->problem.detail, "%s", V(17));
    }
    return 0;
#undef V
}

/* One job by a WHERE on one parameter: STORE_OK, STORE_NOT_FOUND or STORE_IO. */
static int get_where(pg_store *s, const char *where, const char *value, job_record *out)
{
    char sql[512];
    snprintf(sql, sizeof sql, "SELECT " COLS " FROM texopt_jobs WHERE %s", where);
    const char *params[] = {value};
    PGresult *res = exec_sql(s, sql, 1, params);
    if (!res)
        return STORE_IO;
    int rc = PQntuples(res) == 0 ? STORE_NOT_FOUND : row_to_record(res, 0, 0, out) == 0 ? STORE_OK : STORE_IO;
    PQclear(res);
    return rc;
}

static int pg_get(job_store *base, const char *id, job_record *out)
{
    return get_where(as_pg(base), "id = $1", id, out);
}

static int pg_find_key(job_store *base, const char *key, job_record *out)
{
    return get_where(as_pg(base), "idempotency_key = $1", key, out);
}

/* ---- directories --------------------------------------------------------------------- */

static void pg_job_dir(const job_store *base, const char *id, char *dir, size_t dir_len)
{
    snprintf(dir, dir_len, "%s/%s", ((const pg_store *)base)->jobs_dir, id);
}

static int pg_new_job_dir(job_store *base, char *id, char *dir, size_t dir_len)
{
    if (store_random_id(id) != 0)
        return -1;
    pg_job_dir(base, id, dir, dir_len);
    return mkdir(dir, 0750);
}

static void pg_run_dir(job_store *base, store_job *handle, char *dir, size_t dir_len)
{
    (void)base;
    snprintf(dir, dir_len, "%s", ((pg_job *)handle)->run_dir);
}

static int pg_can_store(job_store *base, uint64_t bytes)
{
    pg_store *s = as_pg(base);
    return !atomic_load(&s->unreachable) && store_dir_has_room(s->jobs_dir, bytes);
}

static int pg_unreachable(job_store *base)
{
    return atomic_load(&as_pg(base)->unreachable);
}

/* ---- adding and listing ------------------------------------------------------------- */

static int pg_add(job_store *base, const job_record *record, job_record *existing)
{
    pg_store *s = as_pg(base);
    job_record queued = *record;
    queued.state = JOB_QUEUED;
    queued.event_seq = 1;
    char *description = store_record_to_json(&queued);
    if (!description)
        return STORE_IO;
    char created[32];
    snprintf(created, sizeof created, "%lld", (long long)record->created_ms);
    const char *params[] = {record->id, created, record->idempotency_key, description};
    PGresult *res = exec_sql(s,
                             "INSERT INTO texopt_jobs (id, created_ms, idempotency_key, description, state) "
                             "VALUES ($1, $2, NULLIF($3, ''), $4, 'queued') "
                             "ON CONFLICT (idempotency_key) DO NOTHING "
                             "RETURNING id, pg_notify('texopt_queue', id)",
                             4, params);
    free(description);
    if (!res)
        return STORE_IO;
    int inserted = PQntuples(res) == 1;
    PQclear(res);
    if (inserted) {
        log_event("level=info event=job job=%s state=queued", record->id);
        return STORE_OK;
    }
    /* The key was taken by another request, perhaps on another node. */
    return pg_find_key(base, record->idempotency_key, existing) == STORE_OK ? STORE_DUPLICATE : STORE_IO;
}

static int pg_list(job_store *base, const char *after, job_record *out, int max, int *more)
{
    char limit[16];
    snprintf(limit, sizeof limit, "%d", max + 1);
    const char *params[] = {after ? after : "", limit};
    PGresult *res = exec_sql(as_pg(base),
                             "SELECT " COLS " FROM texopt_jobs WHERE $1 = '' OR (created_ms, id) < "
                             "(SELECT created_ms, id FROM texopt_jobs WHERE id = $1) "
                             "ORDER BY created_ms DESC, id DESC LIMIT $2",
                             2, params);
    *more = 0;
    if (!res)
        return 0;
    int rows = PQntuples(res), n = 0;
    for (int i = 0; i < rows && n < max; i++)
        if (row_to_record(res, i, 0, &out[n]) == 0)
            n++;
    *more = rows > max;
    PQclear(res);
    return n;
}

/* Queued jobs live in the database, not in this node's queue. */
static int pg_queued_ids(job_store *base, char (**ids)[JOB_ID_LEN + 1])
{
    (void)base;
    *ids = calloc(1, sizeof **ids);
    return *ids ? 0 : -1;
}

static void pg_counts(job_store *base, int counts[JOB_STATE_COUNT])
{
    memset(counts, 0, sizeof(int) * JOB_STATE_COUNT);
    PGresult *res = exec_sql(as_pg(base), "SELECT state, count(*) FROM texopt_jobs GROUP BY state", 0, NULL);
    if (!res)
        return;
    for (int i = 0; i < PQntuples(res); i++)
        counts[state_from_name(PQgetvalue(res, i, 0))] = atoi(PQgetvalue(res, i, 1));
    PQclear(res);
}

/* ---- leases ------------------------------------------------------------------------- */

/* The CLOCK_REALTIME time ms from now, for pthread_cond_timedwait. */
static struct timespec realtime_in(int ms)
{
    struct timespec t;
    clock_gettime(CLOCK_REALTIME, &t);
    t.tv_sec += ms / 1000;
    t.tv_nsec += (long)(ms % 1000) * 1000000L;
    if (t.tv_nsec >= 1000000000L) {
        t.tv_sec++;
        t.tv_nsec -= 1000000000L;
    }
    return t;
}

/* Leases the oldest queued job (only job `id` when not empty) to this node. */
static store_job *lease(pg_store *s, const char *id, job_record *out, const atomic_int **cancel)
{
    char lease_ms[16];
    snprintf(lease_ms, sizeof lease_ms, "%d", s->lease_seconds * 1000);
    const char *params[] = {s->node, lease_ms, id};
    PGresult *res = exec_sql(s,
                             "WITH next AS (SELECT id AS next_id FROM texopt_jobs WHERE state = 'queued' "
                             "AND ($3 = '' OR id = $3) ORDER BY created_ms, id LIMIT 1 FOR UPDATE SKIP LOCKED) "
                             "UPDATE texopt_jobs SET state = 'running', attempts = attempts + 1, lease_owner = $1, "
                             "lease_until_ms = " NOW_MS " + $2::bigint, started_ms = " NOW_MS ", stage = '', "
                             "progress = 0, eta_seconds = -1, cancel_requested = false, event_seq = event_seq + 1 "
                             "FROM next WHERE id = next.next_id RETURNING " COLS ", pg_notify('texopt_events', id)",
                             3, params);
    if (!res)
        return NULL;
    pg_job *job = NULL;
    if (PQntuples(res) == 1 && row_to_record(res, 0, 0, out) == 0)
        job = calloc(1, sizeof *job);
    PQclear(res);
    if (!job)
        return NULL; /* an unreadable row stays running and is reaped after its lease */
    memcpy(job->id, out->id, sizeof job->id);
    job->leased_ms = store_now_ms();
    job->published_ms = job->leased_ms;
    /* This node's identity in the name keeps a late run of a lost lease from writing into
     * the run that replaced it. */
    snprintf(job->run_dir, sizeof job->run_dir, "%s/%s/run-%d-%s", s->jobs_dir, out->id, out->attempts, s->node);
    if (fs_mkdir_p(job->run_dir) != 0)
        log_event("level=error event=run-dir job=%s error=\"%s\"", out->id, strerror(errno));
    pthread_mutex_lock(&s->mu);
    job->next = s->running;
    s->running = job;
    pthread_mutex_unlock(&s->mu);
    *cancel = &job->cancel;
    log_event("level=info event=job job=%s state=running attempt=%d node=%s", out->id, out->attempts, s->node);
    return (store_job *)job;
}

static store_job *pg_begin(job_store *base, const char *id, job_record *out, const atomic_int **cancel)
{
    return lease(as_pg(base), id, out, cancel);
}

static store_job *pg_lease_next(job_store *base, int timeout_ms, job_record *out, const atomic_int **cancel)
{
    pg_store *s = as_pg(base);
    pthread_mutex_lock(&s->mu);
    unsigned long gen = s->queue_gen;
    int closing = s->closing;
    pthread_mutex_unlock(&s->mu);
    if (closing)
        return NULL;
    store_job *job = lease(s, "", out, cancel);
    if (job)
        return job;
    struct timespec deadline = realtime_in(timeout_ms);
    pthread_mutex_lock(&s->mu);
    int timed_out = 0;
    while (s->queue_gen == gen && !s->closing && !timed_out)
        timed_out = pthread_cond_timedwait(&s->queue_changed, &s->mu, &deadline) == ETIMEDOUT;
    closing = s->closing;
    pthread_mutex_unlock(&s->mu);
    return closing ? NULL : lease(s, "", out, cancel);
}

static void pg_progress(job_store *base, store_job *handle, const char *stage, double progress, double eta_seconds,
                        double mean_loss, double mean_area_scale)
{
    pg_store *s = as_pg(base);
    pg_job *job = (pg_job *)handle;
    int new_stage = strncmp(job->stage, stage, sizeof job->stage - 1) != 0;
    snprintf(job->stage, sizeof job->stage, "%s", stage);
    if (progress > job->progress)
        job->progress = progress > 1 ? 1 : progress;
    int64_t now = store_now_ms();
    if (!store_progress_worth_publishing(new_stage, job->progress, job->published_progress, now, job->published_ms))
        return;
    job->published_ms = now;
    job->published_progress = job->progress;
    char p[32], eta[32], loss[32], scale[32];
    snprintf(p, sizeof p, "%.17g", job->progress);
    snprintf(eta, sizeof eta, "%.17g", eta_seconds);
    snprintf(loss, sizeof loss, "%.17g", mean_loss);
    snprintf(scale, sizeof scale, "%.17g", mean_area_scale);
    const char *params[] = {job->id, s->node, job->stage, p, eta, loss, scale};
    PGresult *res = exec_sql(s,
                             "UPDATE texopt_jobs SET stage = $3, progress = $4, eta_seconds = $5, mean_loss = $6, "
                             "mean_area_scale = $7, event_seq = event_seq + 1 "
                             "WHERE id = $1 AND lease_owner = $2 AND state = 'running' "
                             "RETURNING pg_notify('texopt_events', id)",
                             7, params);
    PQclear(res);
}

static void forget_running(pg_store *s, pg_job *job)
{
    pthread_mutex_lock(&s->mu);
    for (pg_job **p = &s->running; *p; p = &(*p)->next)
        if (*p == job) {
            *p = job->next;
            break;
        }
    pthread_mutex_unlock(&s->mu);
}

/* Moves the run's outputs into the job directory (each rename atomic) and makes the moves
 * durable before the state that announces them is committed. */
static int publish_outputs(const char *run_dir, const char *job_dir, int has_report)
{
    static const char *const names[] = {"stats.json", "report.html", "result.glb"};
    char from[PATH_MAX + 32], to[PATH_MAX + 32];
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        if (i == 1 && !has_report)
            continue;
        snprintf(from, sizeof from, "%s/%s", run_dir, names[i]);
        snprintf(to, sizeof to, "%s/%s", job_dir, names[i]);
        if (rename(from, to) != 0)
            return -1;
    }
    return fs_sync_parent(to);
}

/* Ends this node's run of job: state is the outcome (JOB_QUEUED puts it back). Only while the
 * node still holds the lease, checked under the row's lock in the same transaction that
 * publishes the outputs and the state. */
static int end_run(pg_store *s, pg_job *job, job_state state, const job_problem *problem, int has_report)
{
    forget_running(s, job);
    job_problem none;
    memset(&none, 0, sizeof none);
    if (!problem || state != JOB_FAILED)
        problem = &none;
    char job_dir[PATH_MAX], status[16];
    pg_job_dir(&s->base, job->id, job_dir, sizeof job_dir);
    snprintf(status, sizeof status, "%d", problem->status);
    const char *id_node[] = {job->id, s->node};
    const char *params[] = {job->id, s->node,       job_state_name(state), has_report ? "true" : "false",
                            status,  problem->type, problem->title,        problem->detail};
    int rc = STORE_IO, slot;
    PGconn *conn = borrow(s, &slot);
    int borrowed = conn != NULL;
    PGresult *res = conn ? exec_on(s, &conn, "BEGIN", 0, NULL) : NULL;
    if (res) {
        PQclear(res);
        res = exec_on(s, &conn,
                      "SELECT 1 FROM texopt_jobs WHERE id = $1 AND lease_owner = $2 AND state = 'running' FOR UPDATE",
                      2, id_node);
        int held = res && PQntuples(res) == 1;
        PQclear(res);
        rc = !res ? STORE_IO : !held ? STORE_CONFLICT : STORE_OK;
        if (rc == STORE_OK && state == JOB_SUCCEEDED && publish_outputs(job->run_dir, job_dir, has_report) != 0) {
            log_event("level=error event=publish job=%s error=\"%s\"", job->id, strerror(errno));
            rc = STORE_IO;
        }
        if (rc == STORE_OK) {
            res = exec_on(s, &conn,
                          "UPDATE texopt_jobs SET state = $3, lease_owner = NULL, cancel_requested = false, "
                          "event_seq = event_seq + 1, has_report = $4, problem_status = $5, problem_type = $6, "
                          "problem_title = $7, problem_detail = $8, "
                          "finished_ms = CASE WHEN $3 IN " FINISHED " THEN " NOW_MS " ELSE 0 END, "
                          "progress = CASE $3 WHEN 'succeeded' THEN 1 WHEN 'queued' THEN 0 ELSE progress END, "
                          "stage = CASE $3 WHEN 'queued' THEN '' ELSE stage END, "
                          "eta_seconds = CASE $3 WHEN 'succeeded' THEN 0 ELSE -1 END "
                          "WHERE id = $1 AND lease_owner = $2 RETURNING pg_notify('texopt_events', id), "
                          "pg_notify(CASE $3 WHEN 'queued' THEN 'texopt_queue' ELSE 'texopt_none' END, id)",
                          8, params);
            rc = res ? STORE_OK : STORE_IO;
            PQclear(res);
        }
        res = exec_on(s, &conn, rc == STORE_OK ? "COMMIT" : "ROLLBACK", 0, NULL);
        if (!res)
            rc = STORE_IO;
        PQclear(res);
    }
    if (borrowed)
        give_back(s, slot, conn);
    if (rc == STORE_CONFLICT)
        log_event("level=warn event=job job=%s action=drop-run reason=lease-lost node=%s", job->id, s->node);
    else if (rc == STORE_OK)
        log_event("level=info event=job job=%s state=%s node=%s", job->id, job_state_name(state), s->node);
    /* Unpublished outputs of a run that did not count go with its directory. */
    fs_remove_tree(job->run_dir);
    free(job);
    return rc;
}

static int pg_finish(job_store *base, store_job *job, job_state state, const job_problem *problem, int has_report)
{
    return end_run(as_pg(base), (pg_job *)job, state, problem, has_report);
}

static int pg_requeue(job_store *base, store_job *job)
{
    return end_run(as_pg(base), (pg_job *)job, JOB_QUEUED, NULL, 0);
}

static void pg_cancel_running(job_store *base)
{
    pg_store *s = as_pg(base);
    pthread_mutex_lock(&s->mu);
    for (pg_job *j = s->running; j; j = j->next)
        atomic_store(&j->cancel, 1);
    pthread_mutex_unlock(&s->mu);
}

/* ---- the node thread: heartbeat, reaping, notifications ---------------------------- */

/* Renews this node's leases; raises the cancel flag of jobs asked to stop and of jobs whose
 * lease this node lost (another node may run them now). */
static int heartbeat(pg_store *s, PGconn **conn)
{
    int64_t started = store_now_ms();
    char lease_ms[16];
    snprintf(lease_ms, sizeof lease_ms, "%d", s->lease_seconds * 1000);
    const char *params[] = {s->node, lease_ms};
    PGresult *res = exec_on(s, conn,
                            "UPDATE texopt_jobs SET lease_until_ms = " NOW_MS " + $2::bigint "
                            "WHERE lease_owner = $1 AND state = 'running' RETURNING id, cancel_requested",
                            2, params);
    if (!res)
        return -1;
    pthread_mutex_lock(&s->mu);
    for (pg_job *j = s->running; j; j = j->next) {
        int found = 0, cancel = 0;
        for (int i = 0; i < PQntuples(res) && !found; i++)
            if (strcmp(PQgetvalue(res, i, 0), j->id) == 0) {
                found = 1;
                cancel = PQgetvalue(res, i, 1)[0] == 't';
            }
        if (lease_lost(found, j->leased_ms, started)) {
            log_event("level=warn event=lease job=%s action=stop reason=lease-lost node=%s", j->id, s->node);
            cancel = 1;
        }
        if (cancel)
            atomic_store(&j->cancel, 1);
    }
    pthread_mutex_unlock(&s->mu);
    PQclear(res);
    return 0;
}

/* Takes back the jobs of nodes whose lease ran out (store_lease.h says what becomes of them). */
static int reap(pg_store *s, PGconn **conn)
{
    PGresult *res = exec_on(s, conn, "BEGIN", 0, NULL);
    if (!res)
        return -1;
    PQclear(res);
    res = exec_on(s, conn,
                  "SELECT id, attempts, cancel_requested, lease_owner FROM texopt_jobs WHERE state = 'running' "
                  "AND lease_until_ms < " NOW_MS " FOR UPDATE SKIP LOCKED",
                  0, NULL);
    int ok = res != NULL;
    for (int i = 0; ok && i < PQntuples(res); i++) {
        const char *id = PQgetvalue(res, i, 0);
        int attempts = atoi(PQgetvalue(res, i, 1));
        job_state next = lease_expired_outcome(attempts, s->max_attempts, PQgetvalue(res, i, 2)[0] == 't');
        job_problem problem;
        memset(&problem, 0, sizeof problem);
        if (next == JOB_FAILED)
            lease_exhausted_problem(attempts, &problem);
        char status[16];
        snprintf(status, sizeof status, "%d", problem.status);
        const char *params[] = {id, job_state_name(next), status, problem.type, problem.title, problem.detail};
        PGresult *done = exec_on(s, conn,
                                 "UPDATE texopt_jobs SET state = $2, lease_owner = NULL, event_seq = event_seq + 1, "
                                 "cancel_requested = false, problem_status = $3, problem_type = $4, "
                                 "problem_title = $5, problem_detail = $6, stage = '', progress = 0, "
                                 "eta_seconds = -1, finished_ms = CASE WHEN $2 = 'queued' THEN 0 ELSE " NOW_MS " END "
                                 "WHERE id = $1 RETURNING pg_notify('texopt_events', id), "
                                 "pg_notify(CASE $2 WHEN 'queued' THEN 'texopt_queue' ELSE 'texopt_none' END, id)",
                                 6, params);
        ok = done != NULL;
        PQclear(done);
        if (ok)
            log_event("level=info event=recover job=%s action=%s reason=lease-expired owner=%s attempts=%d", id,
                      job_state_name(next), PQgetvalue(res, i, 3), attempts);
    }
    PQclear(res);
    res = exec_on(s, conn, ok ? "COMMIT" : "ROLLBACK", 0, NULL);
    ok = ok && res;
    PQclear(res);
    return ok ? 0 : -1;
}

static PGconn *connect_listener(pg_store *s)
{
    PGconn *conn = connect_db(s->conninfo);
    if (!conn)
        return NULL;
    PGresult *res = exec_on(s, &conn, "LISTEN texopt_queue", 0, NULL);
    PGresult *res2 = res ? exec_on(s, &conn, "LISTEN texopt_events", 0, NULL) : NULL;
    if (!res2) {
        PQclear(res);
        PQfinish(conn);
        return NULL;
    }
    PQclear(res);
    PQclear(res2);
    return conn;
}

static void take_notifications(pg_store *s, PGconn *conn)
{
    if (!PQconsumeInput(conn))
        return;
    int queue = 0, events = 0;
    PGnotify *n;
    while ((n = PQnotifies(conn)) != NULL) {
        if (strcmp(n->relname, "texopt_queue") == 0)
            queue = 1;
        else
            events = 1;
        PQfreemem(n);
    }
    pthread_mutex_lock(&s->mu);
    if (queue) {
        s->queue_gen++;
        pthread_cond_broadcast(&s->queue_changed);
    }
    if (events) {
        s->events_gen++;
        pthread_cond_broadcast(&s->events_changed);
    }
    pthread_mutex_unlock(&s->mu);
}

static int is_closing(pg_store *s)
{
    pthread_mutex_lock(&s->mu);
    int closing = s->closing;
    pthread_mutex_unlock(&s->mu);
    return closing;
}

static void *node_main(void *arg)
{
    pg_store *s = arg;
    PGconn *conn = NULL;
    int tick = lease_heartbeat_ms(s->lease_seconds);
    int64_t next_beat = 0;
    while (!is_closing(s)) {
        if (!conn && !(conn = connect_listener(s))) {
            atomic_store(&s->unreachable, 1);
            usleep(200 * 1000);
            continue;
        }
        int64_t now = store_now_ms();
        if (now >= next_beat) {
            PGconn *listening = conn;
            int ok = heartbeat(s, &conn) == 0 && reap(s, &conn) == 0;
            atomic_store(&s->unreachable, !ok);
            next_beat = now + tick;
            if (conn != listening) { /* replaced by a reconnect: it listens to nothing */
                PQfinish(conn);
                conn = NULL;
                continue;
            }
        }
        struct pollfd pfd = {PQsocket(conn), POLLIN, 0};
        int wait = (int)(next_beat - store_now_ms());
        poll(&pfd, 1, wait < 0 ? 0 : wait > 200 ? 200 : wait);
        take_notifications(s, conn);
        if (PQstatus(conn) != CONNECTION_OK) {
            PQfinish(conn);
            conn = NULL;
        }
    }
    PQfinish(conn);
    return NULL;
}

/* ---- cancel, delete, expire, events ------------------------------------------------- */

static cancel_outcome pg_cancel(job_store *base, const char *id, job_record *out)
{
    pg_store *s = as_pg(base);
    const char *params[] = {id};
    PGresult *res = exec_sql(s,
                             "WITH old AS (SELECT id AS old_id, state AS old_state FROM texopt_jobs WHERE id = $1 "
                             "FOR UPDATE) UPDATE texopt_jobs SET "
                             "state = CASE WHEN old_state = 'queued' THEN 'canceled' ELSE state END, "
                             "finished_ms = CASE WHEN old_state = 'queued' THEN " NOW_MS " ELSE finished_ms END, "
                             "cancel_requested = cancel_requested OR old_state = 'running', "
                             "event_seq = event_seq + CASE WHEN old_state IN ('queued', 'running') THEN 1 ELSE 0 END "
                             "FROM old WHERE id = old.old_id RETURNING old_state, " COLS ", "
                             "pg_notify('texopt_events', id)",
                             1, params);
    if (!res)
        return CANCEL_UNSAVED;
    cancel_outcome outcome = CANCEL_NOT_FOUND;
    if (PQntuples(res) == 1 && row_to_record(res, 0, 1, out) == 0) {
        job_state was = state_from_name(PQgetvalue(res, 0, 0));
        outcome = was == JOB_QUEUED ? CANCEL_DONE : was == JOB_RUNNING ? CANCEL_REQUESTED : CANCEL_FINISHED;
    }
    PQclear(res);
    if (outcome == CANCEL_REQUESTED) { /* running here: no need to wait for the heartbeat */
        pthread_mutex_lock(&s->mu);
        for (pg_job *j = s->running; j; j = j->next)
            if (strcmp(j->id, id) == 0)
                atomic_store(&j->cancel, 1);
        pthread_mutex_unlock(&s->mu);
    }
    if (outcome == CANCEL_DONE)
        log_event("level=info event=job job=%s state=canceled", id);
    return outcome;
}

static void remove_job_dir(pg_store *s, const char *id)
{
    char dir[PATH_MAX];
    pg_job_dir(&s->base, id, dir, sizeof dir);
    fs_remove_tree(dir);
    log_event("level=info event=job job=%s state=deleted", id);
}

static int pg_delete(job_store *base, const char *id)
{
    pg_store *s = as_pg(base);
    const char *params[] = {id};
    PGresult *res = exec_sql(
        s, "DELETE FROM texopt_jobs WHERE id = $1 AND state IN " FINISHED " RETURNING pg_notify('texopt_events', id)",
        1, params);
    if (!res)
        return STORE_IO;
    int deleted = PQntuples(res) == 1;
    PQclear(res);
    if (deleted) {
        remove_job_dir(s, id);
        return STORE_OK;
    }
    job_record r;
    int rc = pg_get(base, id, &r);
    return rc == STORE_OK ? STORE_CONFLICT : rc;
}

static int is_job_id(const char *name)
{
    size_t n = strspn(name, "0123456789abcdef");
    return n == JOB_ID_LEN && name[n] == '\0';
}

/* "{id,id,...}": the job directories older than ORPHAN_AGE_SECONDS, as a text[] literal
 * (ids are hex). NULL when there are none. Caller frees. */
static char *old_job_dirs(const pg_store *s, time_t now)
{
    DIR *d = opendir(s->jobs_dir);
    if (!d)
        return NULL;
    char *list = NULL;
    size_t len = 0, cap = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        char path[PATH_MAX];
        struct stat st;
        snprintf(path, sizeof path, "%s/%s", s->jobs_dir, e->d_name);
        if (!is_job_id(e->d_name) || stat(path, &st) != 0 || st.st_mtime > now - ORPHAN_AGE_SECONDS)
            continue;
        if (len + JOB_ID_LEN + 3 > cap) {
            cap = cap ? cap * 2 : 64 * (JOB_ID_LEN + 1);
            char *grown = realloc(list, cap);
            if (!grown)
                break;
            list = grown;
        }
        len += (size_t)snprintf(list + len, cap - len, "%c%s", len ? ',' : '{', e->d_name);
    }
    closedir(d);
    if (list)
        snprintf(list + len, cap - len, "}");
    return list;
}

/* Removes the directories of uploads whose node died before the job was recorded. */
static void remove_orphan_uploads(pg_store *s)
{
    char *ids = old_job_dirs(s, time(NULL));
    if (!ids)
        return;
    const char *params[] = {ids};
    PGresult *res = exec_sql(s,
                             "SELECT u.id FROM unnest($1::text[]) AS u(id) "
                             "WHERE NOT EXISTS (SELECT 1 FROM texopt_jobs j WHERE j.id = u.id)",
                             1, params);
    free(ids);
    for (int i = 0; res && i < PQntuples(res); i++) {
        char dir[PATH_MAX];
        pg_job_dir(&s->base, PQgetvalue(res, i, 0), dir, sizeof dir);
        log_event("level=info event=recover dir=%s action=remove reason=no-job-row", PQgetvalue(res, i, 0));
        fs_remove_tree(dir);
    }
    PQclear(res);
}

/* Also sweeps the blob directory for orphaned uploads (the on-disk store does that at open). */
static int pg_expire(job_store *base, int64_t now_ms, int64_t retention_ms)
{
    pg_store *s = as_pg(base);
    remove_orphan_uploads(s);
    char before[32];
    snprintf(before, sizeof before, "%lld", (long long)(now_ms - retention_ms));
    const char *params[] = {before};
    PGresult *res = exec_sql(s,
                             "DELETE FROM texopt_jobs WHERE state IN " FINISHED " AND finished_ms < $1 "
                             "RETURNING id, pg_notify('texopt_events', id)",
                             1, params);
    if (!res)
        return 0;
    int n = PQntuples(res);
    for (int i = 0; i < n; i++)
        remove_job_dir(s, PQgetvalue(res, i, 0));
    PQclear(res);
    return n;
}

static int pg_wait_event(job_store *base, const char *id, long long after_seq, int timeout_ms, job_record *out)
{
    pg_store *s = as_pg(base);
    int64_t deadline = store_now_ms() + timeout_ms;
    for (;;) {
        pthread_mutex_lock(&s->mu);
        unsigned long gen = s->events_gen;
        int closing = s->closing;
        pthread_mutex_unlock(&s->mu);
        if (closing)
            return -4;
        int rc = pg_get(base, id, out);
        if (rc == STORE_NOT_FOUND)
            return STORE_NOT_FOUND;
        if (rc == STORE_OK && out->event_seq != after_seq)
            return 1;
        int64_t left = deadline - store_now_ms();
        if (left <= 0)
            return 0;
        struct timespec until = realtime_in(left > WAKE_MS ? WAKE_MS : (int)left);
        pthread_mutex_lock(&s->mu);
        while (s->events_gen == gen && !s->closing)
            if (pthread_cond_timedwait(&s->events_changed, &s->mu, &until) == ETIMEDOUT)
                break;
        pthread_mutex_unlock(&s->mu);
    }
}

static void pg_wake_all(job_store *base)
{
    pg_store *s = as_pg(base);
    pthread_mutex_lock(&s->mu);
    s->closing = 1;
    pthread_cond_broadcast(&s->events_changed);
    pthread_cond_broadcast(&s->queue_changed);
    pthread_mutex_unlock(&s->mu);
}

/* ---- open / close ------------------------------------------------------------------ */

static void pg_close(job_store *base)
{
    pg_store *s = as_pg(base);
    pg_wake_all(base);
    if (s->node_thread_started)
        pthread_join(s->node_thread, NULL);
    for (int i = 0; i < POOL_SIZE; i++)
        PQfinish(s->pool[i]);
    while (s->running) {
        pg_job *next = s->running->next;
        free(s->running);
        s->running = next;
    }
    pthread_mutex_destroy(&s->mu);
    pthread_cond_destroy(&s->pool_free);
    pthread_cond_destroy(&s->queue_changed);
    pthread_cond_destroy(&s->events_changed);
    free(s);
}

/* Creates or upgrades the schema, one node at a time. */
static int migrate(PGconn *conn, char *err, size_t err_len)
{
    PGresult *res = PQexec(conn, "BEGIN; SELECT pg_advisory_xact_lock(" SCHEMA_LOCK_KEY "); "
                                 "CREATE TABLE IF NOT EXISTS texopt_schema (version integer NOT NULL); "
                                 "SELECT coalesce(max(version), 0) FROM texopt_schema");
    if (PQresultStatus(res) != PGRES_TUPLES_OK) {
        texopt_fail(err, err_len, TEXOPT_E_IO, "cannot read the schema version: %s", PQerrorMessage(conn));
        PQclear(res);
        return -1;
    }
    int current = atoi(PQgetvalue(res, 0, 0)), first = 0;
    PQclear(res);
    char why[300];
    if (pg_schema_plan(current, &first, why, sizeof why) != 0) {
        texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "%s", why);
        PQclear(PQexec(conn, "ROLLBACK"));
        return -1;
    }
    for (int v = first; v <= pg_schema_latest(); v++) {
        res = PQexec(conn, pg_schema_migration(v));
        int ok = PQresultStatus(res) == PGRES_COMMAND_OK;
        PQclear(res);
        if (!ok) {
            texopt_fail(err, err_len, TEXOPT_E_IO, "schema migration %d failed: %s", v, PQerrorMessage(conn));
            PQclear(PQexec(conn, "ROLLBACK"));
            return -1;
        }
        log_event("level=info event=schema version=%d", v);
    }
    char sql[128];
    snprintf(sql, sizeof sql, "DELETE FROM texopt_schema; INSERT INTO texopt_schema VALUES (%d); COMMIT",
             pg_schema_latest());
    res = PQexec(conn, sql);
    int ok = PQresultStatus(res) == PGRES_COMMAND_OK;
    PQclear(res);
    if (!ok)
        texopt_fail(err, err_len, TEXOPT_E_IO, "cannot record the schema version: %s", PQerrorMessage(conn));
    return ok ? 0 : -1;
}

static const store_ops pg_ops;

job_store *pg_store_open(const service_config *config, char *err, size_t err_len)
{
    pg_store *s = calloc(1, sizeof *s);
    if (!s) {
        texopt_fail(err, err_len, TEXOPT_E_NOMEM, "out of memory");
        return NULL;
    }
    s->base.ops = &pg_ops;
    pthread_mutex_init(&s->mu, NULL);
    pthread_cond_init(&s->pool_free, NULL);
    pthread_cond_init(&s->queue_changed, NULL);
    pthread_cond_init(&s->events_changed, NULL);
    snprintf(s->conninfo, sizeof s->conninfo, "%s", config->store);
    s->lease_seconds = config->lease_seconds;
    s->max_attempts = config->max_attempts;
    char host[64] = "node", suffix[JOB_ID_LEN + 1] = "";
    gethostname(host, sizeof host - 1);
    store_random_id(suffix);
    snprintf(s->node, sizeof s->node, "%s-%ld-%.8s", host, (long)getpid(), suffix);
    snprintf(s->jobs_dir, sizeof s->jobs_dir, "%s/jobs", config->blob_dir[0] ? config->blob_dir : config->data_dir);
    if (fs_mkdir_p(s->jobs_dir) != 0) {
        texopt_fail(err, err_len, TEXOPT_E_IO, "cannot create %s: %s", s->jobs_dir, strerror(errno));
        pg_close(&s->base);
        return NULL;
    }
    char shown[1024];
    store_url_redact(config->store, shown, sizeof shown);
    PGconn *conn = connect_db(s->conninfo);
    if (!conn) {
        texopt_fail(err, err_len, TEXOPT_E_IO, "cannot connect to %s", shown);
        pg_close(&s->base);
        return NULL;
    }
    int migrated = migrate(conn, err, err_len);
    s->pool[0] = conn;
    if (migrated != 0 || pthread_create(&s->node_thread, NULL, node_main, s) != 0) {
        if (migrated == 0)
            texopt_fail(err, err_len, TEXOPT_E_INTERNAL, "cannot start the node thread");
        pg_close(&s->base);
        return NULL;
    }
    s->node_thread_started = 1;
    log_event("level=info event=store kind=postgresql url=%s node=%s blobs=%s lease_seconds=%d max_attempts=%d", shown,
              s->node, s->jobs_dir, s->lease_seconds, s->max_attempts);
    return &s->base;
}

static const store_ops pg_ops = {
    .name = "postgresql",
    .close = pg_close,
    .new_job_dir = pg_new_job_dir,
    .job_dir = pg_job_dir,
    .run_dir = pg_run_dir,
    .add = pg_add,
    .get = pg_get,
    .find_key = pg_find_key,
    .list = pg_list,
    .queued_ids = pg_queued_ids,
    .begin = pg_begin,
    .lease_next = pg_lease_next,
    .progress = pg_progress,
    .finish = pg_finish,
    .requeue = pg_requeue,
    .can_store = pg_can_store,
    .unreachable = pg_unreachable,
    .cancel = pg_cancel,
    .cancel_running = pg_cancel_running,
    .delete_job = pg_delete,
    .expire = pg_expire,
    .wait_event = pg_wait_event,
    .wake_all = pg_wake_all,
    .counts = pg_counts,
};
