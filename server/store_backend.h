/* store_backend.h - what a job store implementation provides (for server/store*.c only).
 *
 * DESIGN. store.h is the one job store API the service calls; a store is a table of
 * operations (store_ops) behind it, chosen at start-up by store_open_config: the on-disk
 * store (store.c, one node, the default) or PostgreSQL (store_pg.c, many nodes sharing one
 * database and one blob directory, built only when libpq is found). Each implementation's
 * struct begins with a job_store, so a job_store * is a pointer to it; the functions of
 * store_dispatch.c forward to the ops. An op that an implementation does not need is NULL
 * and the dispatcher gives its neutral answer (documented in store.h).
 * Does not: hold any state of its own. */
#ifndef TEXOPT_SERVER_STORE_BACKEND_H
#define TEXOPT_SERVER_STORE_BACKEND_H

#include "store.h"

typedef struct store_ops {
    const char *name; /* "disk", "postgresql" */
    void (*close)(job_store *store);
    int (*new_job_dir)(job_store *store, char *id, char *dir, size_t dir_len);
    void (*job_dir)(const job_store *store, const char *id, char *dir, size_t dir_len);
    void (*run_dir)(job_store *store, store_job *job, char *dir, size_t dir_len);
    int (*add)(job_store *store, const job_record *record, job_record *existing);
    int (*get)(job_store *store, const char *id, job_record *out);
    int (*find_key)(job_store *store, const char *key, job_record *out);
    int (*list)(job_store *store, const char *after, job_record *out, int max, int *more);
    int (*queued_ids)(job_store *store, char (**ids)[JOB_ID_LEN + 1]);
    store_job *(*begin)(job_store *store, const char *id, job_record *out, const atomic_int **cancel);
    store_job *(*lease_next)(job_store *store, int timeout_ms, job_record *out, const atomic_int **cancel);
    void (*progress)(job_store *store, store_job *job, const char *stage, double progress, double eta_seconds,
                     double mean_loss, double mean_area_scale);
    int (*finish)(job_store *store, store_job *job, job_state state, const job_problem *problem, int has_report);
    int (*requeue)(job_store *store, store_job *job);
    int (*retry_unsaved)(job_store *store);
    int (*can_store)(job_store *store, uint64_t bytes);
    int (*unreachable)(job_store *store);
    cancel_outcome (*cancel)(job_store *store, const char *id, job_record *out);
    void (*cancel_running)(job_store *store);
    int (*delete_job)(job_store *store, const char *id);
    int (*expire)(job_store *store, int64_t now_ms, int64_t retention_ms);
    int (*wait_event)(job_store *store, const char *id, long long after_seq, int timeout_ms, job_record *out);
    void (*wake_all)(job_store *store);
    void (*counts)(job_store *store, int counts[JOB_STATE_COUNT]);
} store_ops;

struct job_store {
    const store_ops *ops;
};

/* Shared by the implementations (store.c). */

/* job.json's text of a record (caller frees), and back. */
char *store_record_to_json(const job_record *record);
int store_record_from_json(const char *text, job_record *record, char *err, size_t err_len);

/* A fresh random job id (JOB_ID_LEN hex + NUL). 0 or -1. */
int store_random_id(char *id);

/* Whether dir's filesystem has bytes free beyond a reserve for job records. */
int store_dir_has_room(const char *dir, uint64_t bytes);

/* Whether a running job's progress moved enough to publish an event: a new stage, +0.5%,
 * or 250 ms since the last one (watchers are not flooded per triangle). */
int store_progress_worth_publishing(int new_stage, double progress, double published_progress, int64_t now_ms,
                                    int64_t published_ms);

#endif
