/* memory_budget.c - admission of jobs by estimated memory (see memory_budget.h). */
#include "memory_budget.h"

#include <pthread.h>
#include <stdlib.h>

/* The estimate's terms, measured on texopt optimize (docs/benchmarks.md "Under hostile
 * load"): what a job holds besides its images, and per image pixel. */
#define JOB_BASE_BYTES (256ull << 20)
#define JOB_BYTES_PER_PIXEL 28ull

struct memory_budget {
    pthread_mutex_t mu;
    pthread_cond_t freed;
    uint64_t limit, held;
    int running; /* jobs holding a share */
    int closed;
};

memory_budget *memory_budget_create(uint64_t bytes)
{
    if (bytes == 0)
        return NULL;
    memory_budget *b = calloc(1, sizeof *b);
    if (!b)
        return NULL;
    b->limit = bytes;
    pthread_mutex_init(&b->mu, NULL);
    pthread_cond_init(&b->freed, NULL);
    return b;
}

void memory_budget_destroy(memory_budget *budget)
{
    if (!budget)
        return;
    pthread_mutex_destroy(&budget->mu);
    pthread_cond_destroy(&budget->freed);
    free(budget);
}

uint64_t memory_budget_job_bytes(uint64_t pixels)
{
    return JOB_BASE_BYTES + pixels * JOB_BYTES_PER_PIXEL;
}

int memory_budget_acquire(memory_budget *budget, uint64_t need)
{
    pthread_mutex_lock(&budget->mu);
    while (!budget->closed && budget->running > 0 && budget->held + need > budget->limit)
        pthread_cond_wait(&budget->freed, &budget->mu);
    int rc = budget->closed ? -1 : 0;
    if (rc == 0) {
        budget->held += need;
        budget->running++;
    }
    pthread_mutex_unlock(&budget->mu);
    return rc;
}

void memory_budget_release(memory_budget *budget, uint64_t need)
{
    pthread_mutex_lock(&budget->mu);
    budget->held -= need;
    budget->running--;
    pthread_cond_broadcast(&budget->freed);
    pthread_mutex_unlock(&budget->mu);
}

uint64_t memory_budget_held(memory_budget *budget)
{
    pthread_mutex_lock(&budget->mu);
    uint64_t held = budget->held;
    pthread_mutex_unlock(&budget->mu);
    return held;
}

void memory_budget_close(memory_budget *budget)
{
    pthread_mutex_lock(&budget->mu);
    budget->closed = 1;
    pthread_cond_broadcast(&budget->freed);
    pthread_mutex_unlock(&budget->mu);
}
