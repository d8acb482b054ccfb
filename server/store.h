/* store.h - every job the service knows, in memory and on disk.
 *
 * DESIGN. The store owns the jobs. One mutex guards the in-memory records; readers (HTTP
 * threads) take copies (job_record) under it and never hold pointers. A condition variable
 * is broadcast whenever a job publishes an event (state change or progress step), which is
 * what server-sent-event streams wait on. The only pointer handed out is the running-job
 * handle a worker gets from store_begin: a running job is never deleted (DELETE cancels it
 * instead), so the handle stays valid until store_finish/store_requeue.
 *
 * On disk, data_dir/jobs/<id>/ holds the upload (input/...), job.json (the record, written
 * temp + fsync + rename on every state change), and the outputs result.glb, stats.json,
 * report.html. A directory without job.json is an upload that never completed and is
 * removed at open. Jobs found "running" at open were interrupted (crash, kill -9) and go
 * back to "queued". Progress is kept in memory only (it is rebuilt by the re-run).
 * Events are not stored: an event stream sends the latest state of the job, with ids that
 * keep increasing across restarts (the sequence number is in job.json; an interrupted run's
 * unwritten progress events are skipped over by starting the next run's ids at a new
 * epoch).
 *
 * Two implementations sit behind this API (server/store_backend.h): the on-disk store
 * described above (store_open, the default) and PostgreSQL (server/store_pg.h, chosen by
 * --store postgresql://...), where many nodes share the jobs. With a shared store the
 * workers take jobs with store_lease_next instead of the in-process queue. */
#ifndef TEXOPT_SERVER_STORE_H
#define TEXOPT_SERVER_STORE_H

#include <stdatomic.h>
#include <stdint.h>

#include "queue.h"
#include "texopt.h"

typedef enum job_state {
    JOB_QUEUED = 0,
    JOB_RUNNING,
    JOB_SUCCEEDED,
    JOB_FAILED,
    JOB_CANCELED,
    JOB_STATE_COUNT
} job_state;

const char *job_state_name(job_state state);
int job_state_finished(job_state state);

/* RFC 9457 problem details of a failed job. */
typedef struct job_problem {
    int status;
    char type[64];
    char title[96];
    char detail[512];
} job_problem;

struct cJSON;
/* Adds `problem` as the object "problem" of `parent`: the one spelling of a failed job's
 * problem, shared by the API's job view and the store's job.json. */
void job_problem_add_json(struct cJSON *parent, const job_problem *problem);

/* A copy of one job's fields. */
typedef struct job_record {
    char id[JOB_ID_LEN + 1];
    job_state state;
    char stage[16];                              /* engine stage while running; "" before */
    double progress;                             /* 0..1 of the whole job */
    double eta_seconds;                          /* < 0 when unknown */
    double mean_loss, mean_area_scale;           /* running stage-1 statistics */
    int64_t created_ms, started_ms, finished_ms; /* Unix ms; 0 = not yet */
    int attempts;                                /* runs started (an interrupted run is retried) */
    int cancel_requested;
    long long event_seq;  /* id of the latest event */
    char model_name[256]; /* the uploaded model's file name, for Content-Disposition */
    char input_rel[300];  /* the model file, relative to the job directory */
    char idempotency_key[129];
    char request_digest[17]; /* api/fingerprint.h of files + params; "" for older jobs */
    uint64_t upload_bytes;   /* the files uploaded (model and its files), not the envelope */
    int has_report;          /* report.html was written */
    uint64_t image_pixels;   /* width x height over the model's images, from their headers */
    texopt_params params;
    job_problem problem; /* when failed */
} job_record;

typedef struct job_store job_store;
typedef struct store_job store_job; /* a running job's handle (see DESIGN) */

/* Opens (creating) data_dir/jobs and loads every job in it, recovering as described.
 * Returns NULL with a message on failure. */
job_store *store_open(const char *data_dir, char *err, size_t err_len);
struct service_config;
/* The store the configuration asks for: PostgreSQL when config->store is a postgresql://
 * URL (jobs under config->blob_dir, else data_dir), else the on-disk store in data_dir. */
job_store *store_open_config(const struct service_config *config, char *err, size_t err_len);
void store_close(job_store *store);             /* accepts NULL */
const char *store_kind(const job_store *store); /* "disk" or "postgresql" */

/* Whether jobs are shared with other nodes: workers then take them with store_lease_next
 * and the in-process queue stays empty. */
int store_shared(const job_store *store);
/* 1 while the store's database cannot be reached (never for the on-disk store): /readyz
 * fails and uploads are answered 503 + Retry-After. */
int store_unreachable(job_store *store);

/* Makes a fresh job id and its directory; fills id (JOB_ID_LEN + 1) and dir. */
int store_new_job_dir(job_store *store, char *id, char *dir, size_t dir_len);
void store_job_dir(const job_store *store, const char *id, char *dir, size_t dir_len);

/* STORE_IO: the record could not be written or read (a full disk, an unreachable database). */
enum { STORE_OK = 0, STORE_DUPLICATE = 1, STORE_NOT_FOUND = -1, STORE_CONFLICT = -2, STORE_IO = -3 };

/* Adds a new queued job (record->id's directory must exist) and writes its job.json.
 * When another job has the same non-empty idempotency key, adds nothing, copies that job
 * into *existing and returns STORE_DUPLICATE. */
int store_add(job_store *store, const job_record *record, job_record *existing);

/* Copies job id into *out. STORE_OK, STORE_NOT_FOUND or STORE_IO. */
int store_get(job_store *store, const char *id, job_record *out);

/* Copies the job created with idempotency key (non-empty). STORE_OK or STORE_NOT_FOUND. */
int store_find_key(job_store *store, const char *key, job_record *out);

/* Up to max jobs, newest first, starting after job `after` (NULL = from the newest).
 * Returns how many were copied; *more says whether older ones remain. */
int store_list(job_store *store, const char *after, job_record *out, int max, int *more);

/* Ids of the queued jobs, oldest first (for re-queuing after open). Caller frees. */
int store_queued_ids(job_store *store, char (**ids)[JOB_ID_LEN + 1]);

/* queued -> running for a worker. Returns the handle and the cancel flag the engine
 * watches, or NULL when the job is no longer queued (canceled or deleted meanwhile). */
store_job *store_begin(job_store *store, const char *id, job_record *out, const atomic_int **cancel);

/* A shared store: leases the oldest job that is queued, or running on a node whose lease
 * ran out, marks it running on this node and returns it as store_begin does. Waits at most
 * timeout_ms for one; NULL when there is none (always NULL for the on-disk store). */
store_job *store_lease_next(job_store *store, int timeout_ms, job_record *out, const atomic_int **cancel);

/* Where a running job writes its outputs (result.glb, stats.json, report.html): the job
 * directory for the on-disk store; a directory of this run for a shared store, whose
 * store_finish moves them into the job directory when, and only when, the run is still the
 * job's (its lease was not lost). */
void store_run_dir(job_store *store, store_job *job, char *dir, size_t dir_len);

/* A running job's progress (kept when lower than the last: it never runs backwards within
 * a run); publishes an event when it moved enough to matter (a new stage, +0.5% or 250 ms
 * later), so watchers are not flooded per triangle. */
void store_progress(job_store *store, store_job *job, const char *stage, double progress, double eta_seconds,
                    double mean_loss, double mean_area_scale);

/* running -> succeeded/failed/canceled (problem used when failed; has_report: report.html
 * was written). The new state is written to job.json first; when that fails (a full disk)
 * the job stays "running", as on disk, and STORE_IO is returned: store_retry_unsaved
 * writes it later. Either way the caller is done with the handle. */
int store_finish(job_store *store, store_job *job, job_state state, const job_problem *problem, int has_report);
/* running -> queued, for a job stopped by shutdown; it runs again after restart. As
 * store_finish. */
int store_requeue(job_store *store, store_job *job);

/* Writes the ends of runs that could not be written before; each becomes visible once on
 * disk. Returns how many are still unwritten. Called once a second. */
int store_retry_unsaved(job_store *store);

/* Whether an upload of `bytes` can be stored now: every job's state is on disk and the data
 * directory's filesystem has that much free beyond a reserve for job records. */
int store_can_store(job_store *store, uint64_t bytes);

typedef enum cancel_outcome {
    CANCEL_NOT_FOUND,
    CANCEL_DONE,      /* it was queued and is now canceled */
    CANCEL_REQUESTED, /* it is running and stops at the next checkpoint */
    CANCEL_FINISHED,  /* it had already finished: nothing to cancel */
    CANCEL_UNSAVED    /* it is queued, and stays so: the cancel could not be written */
} cancel_outcome;
/* Cancels job id; *out gets the job after the call. The caller removes a canceled queued
 * job from the job queue. */
cancel_outcome store_cancel(job_store *store, const char *id, job_record *out);

/* Raises the cancel flag of every running job (shutdown). */
void store_cancel_running(job_store *store);

/* Removes a finished job and its directory. STORE_OK, STORE_NOT_FOUND or STORE_CONFLICT
 * (not finished). */
int store_delete(job_store *store, const char *id);

/* Deletes finished jobs that finished before now_ms - retention_ms. Returns how many. */
int store_expire(job_store *store, int64_t now_ms, int64_t retention_ms);

/* Waits until job id has an event other than after_seq (newer, or any when after_seq is
 * from the future: a stale client), the timeout passes or the store is
 * shutting down. Returns 1 (new event, *out filled), 0 (timeout, *out filled), or
 * STORE_NOT_FOUND; -4 when shutting down. */
int store_wait_event(job_store *store, const char *id, long long after_seq, int timeout_ms, job_record *out);
/* Wakes every store_wait_event caller for good (shutdown). */
void store_wake_all(job_store *store);

/* Number of jobs in each state. */
void store_counts(job_store *store, int counts[JOB_STATE_COUNT]);

int64_t store_now_ms(void);

#endif
