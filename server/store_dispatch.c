/* store_dispatch.c - the store.h API over an implementation's ops (store_backend.h), and the
 * choice of implementation from the configuration. Does not: store anything itself. */
#include "store_backend.h"

#include <stdio.h>

#include "config.h"
#include "texopt.h"
#ifdef TEXOPT_HAVE_POSTGRES
#include "store_pg.h"
#endif
#include "store_url.h"

job_store *store_open_config(const service_config *config, char *err, size_t err_len)
{
    switch (store_url_kind(config->store)) {
    case STORE_URL_DISK: return store_open(config->data_dir, err, err_len);
    case STORE_URL_POSTGRES:
#ifdef TEXOPT_HAVE_POSTGRES
        return pg_store_open(config, err, err_len);
#else
        texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                    "--store: this texoptd was built without PostgreSQL (libpq was not found)");
        return NULL;
#endif
    default:
        texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                    "--store: '%.40s...' is not a postgresql:// or postgres:// URL", config->store);
        return NULL;
    }
}

void store_close(job_store *store)
{
    if (store)
        store->ops->close(store);
}

const char *store_kind(const job_store *store)
{
    return store->ops->name;
}

int store_shared(const job_store *store)
{
    return store->ops->lease_next != NULL;
}

int store_unreachable(job_store *store)
{
    return store->ops->unreachable ? store->ops->unreachable(store) : 0;
}

int store_new_job_dir(job_store *store, char *id, char *dir, size_t dir_len)
{
    return store->ops->new_job_dir(store, id, dir, dir_len);
}

void store_job_dir(const job_store *store, const char *id, char *dir, size_t dir_len)
{
    store->ops->job_dir(store, id, dir, dir_len);
}

void store_run_dir(job_store *store, store_job *job, char *dir, size_t dir_len)
{
    store->ops->run_dir(store, job, dir, dir_len);
}

int store_add(job_store *store, const job_record *record, job_record *existing)
{
    return store->ops->add(store, record, existing);
}

int store_get(job_store *store, const char *id, job_record *out)
{
    return store->ops->get(store, id, out);
}

int store_find_key(job_store *store, const char *key, job_record *out)
{
    return store->ops->find_key(store, key, out);
}

int store_list(job_store *store, const char *after, job_record *out, int max, int *more)
{
    return store->ops->list(store, after, out, max, more);
}

int store_queued_ids(job_store *store, char (**ids)[JOB_ID_LEN + 1])
{
    return store->ops->queued_ids(store, ids);
}

store_job *store_begin(job_store *store, const char *id, job_record *out, const atomic_int **cancel)
{
    return store->ops->begin(store, id, out, cancel);
}

store_job *store_lease_next(job_store *store, int timeout_ms, job_record *out, const atomic_int **cancel)
{
    return store->ops->lease_next ? store->ops->lease_next(store, timeout_ms, out, cancel) : NULL;
}

void store_progress(job_store *store, store_job *job, const char *stage, double progress, double eta_seconds,
                    double mean_loss, double mean_area_scale)
{
    store->ops->progress(store, job, stage, progress, eta_seconds, mean_loss, mean_area_scale);
}

int store_finish(job_store *store, store_job *job, job_state state, const job_problem *problem, int has_report)
{
    return store->ops->finish(store, job, state, problem, has_report);
}

int store_requeue(job_store *store, store_job *job)
{
    return store->ops->requeue(store, job);
}

int store_retry_unsaved(job_store *store)
{
    return store->ops->retry_unsaved ? store->ops->retry_unsaved(store) : 0;
}

int store_can_store(job_store *store, uint64_t bytes)
{
    return store->ops->can_store(store, bytes);
}

cancel_outcome store_cancel(job_store *store, const char *id, job_record *out)
{
    return store->ops->cancel(store, id, out);
}

void store_cancel_running(job_store *store)
{
    store->ops->cancel_running(store);
}

int store_delete(job_store *store, const char *id)
{
    return store->ops->delete_job(store, id);
}

int store_expire(job_store *store, int64_t now_ms, int64_t retention_ms)
{
    return store->ops->expire(store, now_ms, retention_ms);
}

int store_wait_event(job_store *store, const char *id, long long after_seq, int timeout_ms, job_record *out)
{
    return store->ops->wait_event(store, id, after_seq, timeout_ms, out);
}

void store_wake_all(job_store *store)
{
    store->ops->wake_all(store);
}

void store_counts(job_store *store, int counts[JOB_STATE_COUNT])
{
    store->ops->counts(store, counts);
}
