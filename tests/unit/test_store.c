/* test_store.c - the job store: records survive reopening (the restart path), interrupted
 * jobs come back queued, half uploads are removed, idempotency keys, cancel/delete rules,
 * listing order, event waiting, expiry. Each test uses its own temporary data directory. */
#define _DEFAULT_SOURCE
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fsutil.h"
#include "store.h"
#include "test.h"

static char *temp_dir(char *buf)
{
    strcpy(buf, "/tmp/texopt-store-test.XXXXXX");
    return mkdtemp(buf);
}

/* A store in a fresh temporary data directory (root: 64 bytes), or NULL. */
static job_store *open_temp_store(char *root)
{
    char err[256] = "";
    if (!temp_dir(root))
        return NULL;
    job_store *s = store_open(root, err, sizeof err);
    if (!s)
        fprintf(stderr, "store_open: %s\n", err);
    return s;
}

static void close_temp_store(job_store *s, const char *root)
{
    store_close(s);
    fs_remove_tree(root);
}

/* A queued record in a fresh job directory. */
static int new_job(job_store *s, job_record *r, const char *key, int64_t created_ms)
{
    char dir[PATH_MAX];
    memset(r, 0, sizeof *r);
    if (store_new_job_dir(s, r->id, dir, sizeof dir) != 0)
        return -1;
    r->created_ms = created_ms;
    snprintf(r->input_rel, sizeof r->input_rel, "input/model.glb");
    snprintf(r->model_name, sizeof r->model_name, "spot.glb");
    snprintf(r->idempotency_key, sizeof r->idempotency_key, "%s", key);
    snprintf(r->request_digest, sizeof r->request_digest, "00112233aabbccdd");
    texopt_params_resolve(&r->params);
    r->params.method = TEXOPT_METHOD_INPUT;
    r->params.iterations = 17;
    job_record existing;
    return store_add(s, r, &existing);
}

TEST(records_survive_reopening)
{
    char root[64], err[256] = "";
    job_store *s = open_temp_store(root);
    CHECK(s != NULL);
    job_record a;
    CHECK_EQ_INT(new_job(s, &a, "", 1000), STORE_OK);
    store_close(s);
    s = store_open(root, err, sizeof err);
    CHECK(s != NULL);
    job_record b;
    CHECK_EQ_INT(store_get(s, a.id, &b), STORE_OK);
    CHECK_EQ_INT(b.state, JOB_QUEUED);
    CHECK_EQ_INT(b.params.method, TEXOPT_METHOD_INPUT);
    CHECK_EQ_INT(b.params.iterations, 17);
    CHECK(strcmp(b.model_name, "spot.glb") == 0);
    CHECK(strcmp(b.input_rel, "input/model.glb") == 0);
    CHECK(strcmp(b.request_digest, "00112233aabbccdd") == 0);
    CHECK_EQ_INT(b.created_ms, 1000);
    close_temp_store(s, root);
}

TEST(interrupted_jobs_come_back_queued_and_finished_ones_stay)
{
    char root[64], err[256] = "";
    job_store *s = open_temp_store(root);
    CHECK(s != NULL);
    job_record a, b, got;
    CHECK_EQ_INT(new_job(s, &a, "", 1), STORE_OK);
    CHECK_EQ_INT(new_job(s, &b, "", 2), STORE_OK);
    const atomic_int *cancel;
    store_job *ja = store_begin(s, a.id, &got, &cancel);
    CHECK(ja != NULL);
    CHECK_EQ_INT(got.state, JOB_RUNNING);
    CHECK_EQ_INT(got.attempts, 1);
    CHECK(store_begin(s, a.id, &got, &cancel) == NULL); /* not queued any more */
    /* Progress events are not written to disk; the ids a client saw must stay below the
     * ids after recovery. */
    for (int i = 1; i <= 40; i++)
        store_progress(s, ja, "stage1", i * 0.02, -1, 0, 0);
    CHECK_EQ_INT(store_get(s, a.id, &got), STORE_OK);
    long long seen = got.event_seq;
    CHECK(seen >= 40);
    store_job *jb = store_begin(s, b.id, &got, &cancel);
    CHECK(jb != NULL);
    store_finish(s, jb, JOB_SUCCEEDED, NULL, 0);
    /* A crash now: the second store sees what is on disk, as a restarted texoptd would. */
    job_store *after = store_open(root, err, sizeof err);
    CHECK(after != NULL);
    CHECK_EQ_INT(store_get(after, a.id, &got), STORE_OK);
    CHECK_EQ_INT(got.state, JOB_QUEUED);
    CHECK_EQ_INT(got.attempts, 1);
    CHECK(got.event_seq > seen);
    CHECK_EQ_INT(got.progress, 0);
    CHECK_EQ_INT(store_get(after, b.id, &got), STORE_OK);
    CHECK_EQ_INT(got.state, JOB_SUCCEEDED);
    CHECK_NEAR(got.progress, 1.0, 0);
    char(*ids)[JOB_ID_LEN + 1];
    CHECK_EQ_INT(store_queued_ids(after, &ids), 1);
    CHECK(strcmp(ids[0], a.id) == 0);
    free(ids);
    store_close(after);
    close_temp_store(s, root);
}

TEST(a_directory_without_job_json_is_removed_at_open)
{
    char root[64], err[256] = "", half[PATH_MAX];
    CHECK(temp_dir(root));
    snprintf(half, sizeof half, "%s/jobs/abcdefabcdefabcdefabcdefabcdefab/input", root);
    CHECK(fs_mkdir_p(half) == 0);
    job_store *s = store_open(root, err, sizeof err);
    CHECK(s != NULL);
    snprintf(half, sizeof half, "%s/jobs/abcdefabcdefabcdefabcdefabcdefab", root);
    CHECK(access(half, F_OK) != 0);
    close_temp_store(s, root);
}

TEST(an_idempotency_key_returns_the_first_job)
{
    char root[64];
    job_store *s = open_temp_store(root);
    CHECK(s != NULL);
    job_record a, b, existing;
    CHECK_EQ_INT(new_job(s, &a, "key-1", 1), STORE_OK);
    char dir[PATH_MAX];
    memset(&b, 0, sizeof b);
    CHECK(store_new_job_dir(s, b.id, dir, sizeof dir) == 0);
    snprintf(b.idempotency_key, sizeof b.idempotency_key, "key-1");
    snprintf(b.input_rel, sizeof b.input_rel, "input/model.glb");
    texopt_params_resolve(&b.params);
    CHECK_EQ_INT(store_add(s, &b, &existing), STORE_DUPLICATE);
    CHECK(strcmp(existing.id, a.id) == 0);
    CHECK_EQ_INT(store_find_key(s, "key-1", &existing), STORE_OK);
    CHECK(strcmp(existing.id, a.id) == 0);
    CHECK_EQ_INT(store_find_key(s, "key-2", &existing), STORE_NOT_FOUND);
    close_temp_store(s, root);
}

TEST(cancel_and_delete_follow_the_state)
{
    char root[64], dir[PATH_MAX];
    job_store *s = open_temp_store(root);
    CHECK(s != NULL);
    job_record q, r, got;
    CHECK_EQ_INT(new_job(s, &q, "", 1), STORE_OK);
    CHECK_EQ_INT(new_job(s, &r, "", 2), STORE_OK);
    const atomic_int *cancel;
    store_job *jr = store_begin(s, r.id, &got, &cancel);
    CHECK(jr != NULL && atomic_load(cancel) == 0);

    CHECK_EQ_INT(store_delete(s, r.id), STORE_CONFLICT);    /* running: not deletable */
    CHECK_EQ_INT(store_cancel(s, q.id, &got), CANCEL_DONE); /* queued: canceled now */
    CHECK_EQ_INT(got.state, JOB_CANCELED);
    CHECK_EQ_INT(store_cancel(s, r.id, &got), CANCEL_REQUESTED); /* running: flag raised */
    CHECK_EQ_INT(got.state, JOB_RUNNING);
    CHECK(got.cancel_requested);
    CHECK(atomic_load(cancel) == 1);
    store_finish(s, jr, JOB_CANCELED, NULL, 0);
    CHECK_EQ_INT(store_cancel(s, r.id, &got), CANCEL_FINISHED);
    CHECK_EQ_INT(store_cancel(s, "ffffffffffffffffffffffffffffffff", &got), CANCEL_NOT_FOUND);

    CHECK_EQ_INT(store_delete(s, q.id), STORE_OK);
    store_job_dir(s, q.id, dir, sizeof dir);
    CHECK(access(dir, F_OK) != 0);
    CHECK_EQ_INT(store_get(s, q.id, &got), STORE_NOT_FOUND);
    CHECK_EQ_INT(store_delete(s, q.id), STORE_NOT_FOUND);
    close_temp_store(s, root);
}

TEST(failed_jobs_keep_their_problem_across_reopening)
{
    char root[64], err[256] = "";
    job_store *s = open_temp_store(root);
    CHECK(s != NULL);
    job_record a, got;
    CHECK_EQ_INT(new_job(s, &a, "", 1), STORE_OK);
    const atomic_int *cancel;
    store_job *j = store_begin(s, a.id, &got, &cancel);
    job_problem p = {422, "urn:texopt:problem:unsupported-model", "unsupported", "domain 0: no texture"};
    store_finish(s, j, JOB_FAILED, &p, 0);
    job_store *again = store_open(root, err, sizeof err);
    CHECK_EQ_INT(store_get(again, a.id, &got), STORE_OK);
    CHECK_EQ_INT(got.state, JOB_FAILED);
    CHECK_EQ_INT(got.problem.status, 422);
    CHECK(strcmp(got.problem.detail, "domain 0: no texture") == 0);
    store_close(again);
    close_temp_store(s, root);
}

TEST(list_is_newest_first_and_pages)
{
    char root[64];
    job_store *s = open_temp_store(root);
    CHECK(s != NULL);
    job_record jobs[5], page[2];
    for (int i = 0; i < 5; i++)
        CHECK_EQ_INT(new_job(s, &jobs[i], "", 100 + i), STORE_OK);
    int more = 0;
    CHECK_EQ_INT(store_list(s, NULL, page, 2, &more), 2);
    CHECK(more);
    CHECK(strcmp(page[0].id, jobs[4].id) == 0 && strcmp(page[1].id, jobs[3].id) == 0);
    CHECK_EQ_INT(store_list(s, page[1].id, page, 2, &more), 2);
    CHECK(strcmp(page[0].id, jobs[2].id) == 0 && strcmp(page[1].id, jobs[1].id) == 0);
    CHECK(more);
    CHECK_EQ_INT(store_list(s, page[1].id, page, 2, &more), 1);
    CHECK(strcmp(page[0].id, jobs[0].id) == 0);
    CHECK(!more);
    int counts[JOB_STATE_COUNT];
    store_counts(s, counts);
    CHECK_EQ_INT(counts[JOB_QUEUED], 5);
    CHECK_EQ_INT(counts[JOB_RUNNING], 0);
    close_temp_store(s, root);
}

typedef struct progress_thread {
    job_store *store;
    store_job *job;
} progress_thread;

static void *report_later(void *arg)
{
    progress_thread *t = arg;
    usleep(50000);
    store_progress(t->store, t->job, "stage1", 0.4, 12.0, 0.002, 0.6);
    return NULL;
}

TEST(event_waiters_wake_on_progress_and_time_out_otherwise)
{
    char root[64];
    job_store *s = open_temp_store(root);
    CHECK(s != NULL);
    job_record a, got;
    CHECK_EQ_INT(new_job(s, &a, "", 1), STORE_OK);
    const atomic_int *cancel;
    store_job *j = store_begin(s, a.id, &got, &cancel);
    long long seq = got.event_seq;
    CHECK_EQ_INT(store_wait_event(s, a.id, seq, 30, &got), 0); /* nothing new: timeout */
    progress_thread t = {s, j};
    pthread_t th;
    pthread_create(&th, NULL, report_later, &t);
    CHECK_EQ_INT(store_wait_event(s, a.id, seq, 5000, &got), 1);
    pthread_join(th, NULL);
    CHECK(got.event_seq > seq);
    CHECK(strcmp(got.stage, "stage1") == 0);
    CHECK_NEAR(got.progress, 0.4, 1e-12);
    CHECK_NEAR(got.eta_seconds, 12.0, 1e-12);
    CHECK_NEAR(got.mean_loss, 0.002, 1e-12);
    /* A tiny step right after is coalesced: no new event. */
    long long before = got.event_seq;
    store_progress(s, j, "stage1", 0.401, 11.9, 0.002, 0.6);
    CHECK_EQ_INT(store_get(s, a.id, &got), STORE_OK);
    CHECK_EQ_INT(got.event_seq, before);
    CHECK_NEAR(got.progress, 0.401, 1e-12);
    /* A later stage reporting less (an evaluation starting at its own zero) does not move
     * it back. */
    store_progress(s, j, "compare", 0.2, -1, 0.002, 0.6);
    CHECK_EQ_INT(store_get(s, a.id, &got), STORE_OK);
    CHECK_NEAR(got.progress, 0.401, 1e-12);
    CHECK(strcmp(got.stage, "compare") == 0);
    /* A client claiming an id the job never reached gets the current state at once. */
    CHECK_EQ_INT(store_wait_event(s, a.id, got.event_seq + 1000, 5000, &got), 1);
    store_wake_all(s);
    CHECK_EQ_INT(store_wait_event(s, a.id, got.event_seq, 5000, &got), -4);
    CHECK_EQ_INT(store_wait_event(s, "ffffffffffffffffffffffffffffffff", 0, 10, &got), -4);
    store_finish(s, j, JOB_SUCCEEDED, NULL, 0);
    close_temp_store(s, root);
}

TEST(expiry_removes_only_old_finished_jobs)
{
    char root[64];
    job_store *s = open_temp_store(root);
    CHECK(s != NULL);
    job_record a, b, got;
    CHECK_EQ_INT(new_job(s, &a, "", 1), STORE_OK);
    CHECK_EQ_INT(new_job(s, &b, "", 2), STORE_OK);
    CHECK_EQ_INT(store_cancel(s, a.id, &got), CANCEL_DONE);
    int64_t finished = got.finished_ms;
    CHECK_EQ_INT(store_expire(s, finished + 1000, 5000), 0);
    CHECK_EQ_INT(store_expire(s, finished + 6000, 5000), 1);
    CHECK_EQ_INT(store_get(s, a.id, &got), STORE_NOT_FOUND);
    CHECK_EQ_INT(store_get(s, b.id, &got), STORE_OK); /* queued: never expires */
    close_temp_store(s, root);
}
