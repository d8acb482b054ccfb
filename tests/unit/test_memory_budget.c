/* test_memory_budget.c - jobs are admitted while their estimated memory fits: a second job
 * that would not fit waits for the first to release, one larger than the whole budget runs
 * alone, and closing wakes every waiter without admitting it. */
#define _DEFAULT_SOURCE
#include <pthread.h>
#include <stdatomic.h>
#include <unistd.h>

#include "memory_budget.h"
#include "test.h"

typedef struct waiter {
    memory_budget *budget;
    uint64_t need;
    atomic_int result; /* 1 before the acquire returns */
} waiter;

static void *acquire_later(void *arg)
{
    waiter *w = arg;
    atomic_store(&w->result, memory_budget_acquire(w->budget, w->need));
    return NULL;
}

/* Polls up to a second for the waiter to return; its result, or 1 when still waiting. */
static int result_within_a_second(waiter *w)
{
    for (int i = 0; i < 100 && atomic_load(&w->result) == 1; i++)
        usleep(10000);
    return atomic_load(&w->result);
}

TEST(a_job_that_does_not_fit_waits_for_memory_to_be_released)
{
    memory_budget *b = memory_budget_create(1000);
    CHECK(b != NULL);
    CHECK_EQ_INT(memory_budget_acquire(b, 600), 0);
    waiter w = {b, 600, 1};
    pthread_t t;
    CHECK(pthread_create(&t, NULL, acquire_later, &w) == 0);
    usleep(100000);
    CHECK_EQ_INT(atomic_load(&w.result), 1); /* 600 + 600 > 1000: still waiting */
    CHECK(memory_budget_held(b) == 600);
    memory_budget_release(b, 600);
    CHECK_EQ_INT(result_within_a_second(&w), 0);
    pthread_join(t, NULL);
    CHECK(memory_budget_held(b) == 600);
    CHECK_EQ_INT(memory_budget_acquire(b, 400), 0); /* fits beside it */
    CHECK(memory_budget_held(b) == 1000);
    memory_budget_release(b, 400);
    memory_budget_release(b, 600);
    memory_budget_destroy(b);
}

TEST(a_job_larger_than_the_budget_runs_alone)
{
    memory_budget *b = memory_budget_create(1000);
    CHECK(b != NULL);
    CHECK_EQ_INT(memory_budget_acquire(b, 5000), 0); /* nothing runs: admitted */
    waiter w = {b, 10, 1};
    pthread_t t;
    CHECK(pthread_create(&t, NULL, acquire_later, &w) == 0);
    usleep(100000);
    CHECK_EQ_INT(atomic_load(&w.result), 1);
    memory_budget_release(b, 5000);
    CHECK_EQ_INT(result_within_a_second(&w), 0);
    pthread_join(t, NULL);
    memory_budget_release(b, 10);
    memory_budget_destroy(b);
}

TEST(closing_wakes_waiters_without_admitting_them)
{
    memory_budget *b = memory_budget_create(1000);
    CHECK(b != NULL);
    CHECK_EQ_INT(memory_budget_acquire(b, 900), 0);
    waiter w = {b, 900, 1};
    pthread_t t;
    CHECK(pthread_create(&t, NULL, acquire_later, &w) == 0);
    usleep(50000);
    memory_budget_close(b);
    CHECK_EQ_INT(result_within_a_second(&w), -1);
    pthread_join(t, NULL);
    CHECK(memory_budget_held(b) == 900);
    memory_budget_release(b, 900);
    memory_budget_destroy(b);
}

TEST(the_estimate_grows_with_the_pixels)
{
    CHECK(memory_budget_job_bytes(0) > 0);
    /* A 16000 x 16000 image: more than the 3.2 GB texopt optimize --method input peaked at. */
    CHECK(memory_budget_job_bytes(16000ull * 16000ull) > 3200000000ull);
    CHECK(memory_budget_job_bytes(2000) > memory_budget_job_bytes(1000));
}
