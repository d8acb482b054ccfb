/* test_parallel.c - the engine's worker runner (engine/core/parallel.c): every worker runs once
 * with its own argument, worker 0 on the calling thread and the others at the same time on
 * threads of their own; a shared argument with stride 0; and when no thread can start,
 * every worker still runs, in order, on the calling thread. */
#define _GNU_SOURCE
#include <pthread.h>
#include <stdatomic.h>
#include <time.h>

#include "parallel.h"
#include "test.h"

#define MAX_TEST_WORKERS 8

typedef struct rendezvous {
    atomic_int arrived;
    int expected;
    atomic_int order; /* the order in which workers are called */
} rendezvous;

typedef struct probe {
    rendezvous *rv;
    int calls;
    int called_as;      /* rv->order when it ran */
    int met_the_others; /* saw every worker arrive while it waited */
    pthread_t thread;
} probe;

static double seconds_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Arrives and waits (up to 10 s) for every other worker: only workers running at the same
 * time can all meet. */
static void *meet(void *arg)
{
    probe *p = arg;
    p->calls++;
    p->thread = pthread_self();
    p->called_as = atomic_fetch_add(&p->rv->order, 1);
    atomic_fetch_add(&p->rv->arrived, 1);
    double until = seconds_now() + 10.0;
    while (atomic_load(&p->rv->arrived) < p->rv->expected && seconds_now() < until)
        sched_yield();
    p->met_the_others = atomic_load(&p->rv->arrived) >= p->rv->expected;
    return NULL;
}

static void *count_calls(void *arg)
{
    atomic_fetch_add((atomic_int *)arg, 1);
    return NULL;
}

TEST(every_worker_runs_once_with_its_own_argument_and_all_at_the_same_time)
{
    for (int n = 1; n <= MAX_TEST_WORKERS; n++) {
        rendezvous rv = {.expected = n};
        probe p[MAX_TEST_WORKERS] = {{0}};
        for (int k = 0; k < n; k++)
            p[k].rv = &rv;
        texopt_parallel_run(meet, p, sizeof *p, n);
        CHECK_EQ_INT(atomic_load(&rv.arrived), n);
        for (int k = 0; k < n; k++) {
            CHECK_EQ_INT(p[k].calls, 1);
            CHECK_MSG(p[k].met_the_others, "worker %d of %d did not run beside the others", k, n);
            CHECK_MSG(pthread_equal(p[k].thread, pthread_self()) == (k == 0),
                      "worker %d of %d: only worker 0 runs on the calling thread", k, n);
        }
    }
}

TEST(stride_zero_gives_every_worker_the_same_argument)
{
    atomic_int calls = 0;
    texopt_parallel_run(count_calls, &calls, 0, 5);
    CHECK_EQ_INT(atomic_load(&calls), 5);
}

TEST(fewer_than_one_worker_runs_worker_zero_alone)
{
    atomic_int calls = 0;
    texopt_parallel_run(count_calls, &calls, 0, 0);
    CHECK_EQ_INT(atomic_load(&calls), 1);
    texopt_parallel_run(count_calls, &calls, 0, -3);
    CHECK_EQ_INT(atomic_load(&calls), 2);
}

TEST(workers_whose_threads_cannot_start_run_in_order_on_the_calling_thread)
{
    /* A default stack larger than any address space: every pthread_create fails. */
    pthread_attr_t saved, huge;
    CHECK(pthread_getattr_default_np(&saved) == 0);
    CHECK(pthread_attr_init(&huge) == 0);
    CHECK(pthread_attr_setstacksize(&huge, (size_t)1 << 62) == 0);
    CHECK(pthread_setattr_default_np(&huge) == 0);
    pthread_t t;
    atomic_int calls = 0;
    int could_start = pthread_create(&t, NULL, count_calls, &calls) == 0;
    if (could_start)
        pthread_join(t, NULL);
    rendezvous rv = {.expected = 1}; /* alone on one thread, nobody else to meet */
    probe p[4] = {{0}};
    for (int k = 0; k < 4; k++)
        p[k].rv = &rv;
    texopt_parallel_run(meet, p, sizeof *p, 4);
    CHECK(pthread_setattr_default_np(&saved) == 0);
    pthread_attr_destroy(&huge);
    pthread_attr_destroy(&saved);
    CHECK_MSG(!could_start, "a thread with a 2^62-byte stack started: this test cannot stop threads");
    for (int k = 0; k < 4; k++) {
        CHECK_EQ_INT(p[k].calls, 1);
        CHECK_EQ_INT(p[k].called_as, k);
        CHECK(pthread_equal(p[k].thread, pthread_self()));
    }
}
