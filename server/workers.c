/* workers.c - the worker threads (see the DESIGN comment in workers.h). */
#define _DEFAULT_SOURCE
#include "workers.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "log.h"
#include "memory_budget.h"
#include "run_job.h"
#include "texopt.h"

#define WORKER_NICE 10

struct worker_pool {
    job_store *store;
    job_queue *queue;
    service_metrics *metrics;
    memory_budget *memory;
    pthread_t *threads;
    int count;
    atomic_int busy;
    atomic_int stopping;
    int stopped;
    int nice;
};

/* Engine work yields to HTTP work: a worker runs at a lower priority (nice, per thread on
 * Linux) and the threads the engine starts inherit it, so status requests keep their
 * latency while a job keeps both cores busy. Without it, p99 of polling rises tenfold. */
static void lower_own_priority(int nice_value)
{
    id_t tid = (id_t)syscall(SYS_gettid);
    if (setpriority(PRIO_PROCESS, tid, nice_value) != 0)
        log_event("level=warn event=workers message=\"cannot lower worker priority\"");
}

/* How long a worker of a shared store waits for a job before it checks `stopping` again. */
#define LEASE_WAIT_MS 500

static void run_leased(worker_pool *pool, store_job *job, const job_record *record, const atomic_int *cancel)
{
    atomic_fetch_add(&pool->busy, 1);
    run_job(pool->store, pool->metrics, job, record, cancel, &pool->stopping);
    atomic_fetch_sub(&pool->busy, 1);
}

/* A shared store (store_shared): jobs come from the database's queue, not this node's. The
 * job is leased before its memory is known, so it holds the lease while it waits for the
 * budget (it is running here, not queued, meanwhile). */
static void take_shared_jobs(worker_pool *pool)
{
    while (!atomic_load(&pool->stopping)) {
        job_record record;
        const atomic_int *cancel = NULL;
        store_job *job = store_lease_next(pool->store, LEASE_WAIT_MS, &record, &cancel);
        if (!job)
            continue;
        uint64_t need = memory_budget_job_bytes(record.image_pixels);
        if (atomic_load(&pool->stopping) || memory_budget_acquire(pool->memory, need) != 0) {
            store_requeue(pool->store, job);
            break;
        }
        run_leased(pool, job, &record, cancel);
        memory_budget_release(pool->memory, need);
    }
}

static void *worker_main(void *arg)
{
    worker_pool *pool = arg;
    char id[JOB_ID_LEN + 1];
    lower_own_priority(pool->nice);
    if (store_shared(pool->store)) {
        take_shared_jobs(pool);
        return NULL;
    }
    while (queue_pop(pool->queue, id) == QUEUE_OK) {
        job_record record;
        if (store_get(pool->store, id, &record) != STORE_OK)
            continue; /* deleted while it waited */
        /* Still queued while it waits for memory: it can be canceled meanwhile, and a
         * shutdown leaves it queued on disk. */
        uint64_t need = memory_budget_job_bytes(record.image_pixels);
        if (memory_budget_acquire(pool->memory, need) != 0)
            break;
        const atomic_int *cancel = NULL;
        store_job *job = store_begin(pool->store, id, &record, &cancel);
        if (job && atomic_load(&pool->stopping)) {
            store_requeue(pool->store, job); /* taken just as the service stops */
        } else if (job) {
            run_leased(pool, job, &record, cancel);
        }
        memory_budget_release(pool->memory, need);
    }
    return NULL;
}

worker_pool *workers_start(job_store *store, job_queue *queue, service_metrics *metrics, const service_config *config,
                           char *err, size_t err_len)
{
    worker_pool *pool = calloc(1, sizeof *pool);
    if (pool)
        pool->threads = calloc((size_t)config->workers, sizeof *pool->threads);
    if (!pool || !pool->threads) {
        free(pool);
        texopt_fail(err, err_len, TEXOPT_E_NOMEM, "out of memory");
        return NULL;
    }
    pool->store = store;
    pool->queue = queue;
    pool->metrics = metrics;
    pool->memory = memory_budget_create(config->memory_budget);
    if (!pool->memory) {
        workers_destroy(pool);
        texopt_fail(err, err_len, TEXOPT_E_NOMEM, "out of memory");
        return NULL;
    }
    pool->nice = WORKER_NICE;
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    pthread_attr_setstacksize(&attr, TEXOPT_PARSE_STACK_BYTES);
    for (int i = 0; i < config->workers; i++) {
        if (pthread_create(&pool->threads[i], &attr, worker_main, pool) != 0) {
            pthread_attr_destroy(&attr);
            texopt_fail(err, err_len, TEXOPT_E_INTERNAL, "cannot start worker thread %d", i);
            workers_destroy(pool);
            return NULL;
        }
        pool->count++;
    }
    pthread_attr_destroy(&attr);
    log_event("level=info event=workers started=%d", pool->count);
    return pool;
}

int workers_busy(const worker_pool *pool)
{
    return atomic_load(&pool->busy);
}

int workers_count(const worker_pool *pool)
{
    return pool->count;
}

void workers_stop(worker_pool *pool)
{
    if (pool->stopped)
        return;
    /* This order leaves no gap: a job begun after the cancel sweep sees `stopping`. */
    atomic_store(&pool->stopping, 1);
    queue_close(pool->queue);
    if (pool->memory)
        memory_budget_close(pool->memory);
    store_cancel_running(pool->store);
    for (int i = 0; i < pool->count; i++)
        pthread_join(pool->threads[i], NULL);
    pool->stopped = 1;
}

void workers_destroy(worker_pool *pool)
{
    if (!pool)
        return;
    workers_stop(pool);
    memory_budget_destroy(pool->memory);
    free(pool->threads);
    free(pool);
}
