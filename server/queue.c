/* queue.c - FIFO of job ids, mutex + condition variable (see the DESIGN comment in queue.h).
 * A ring buffer sized at creation; restored jobs beyond the limit grow it. */
#include "queue.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

typedef struct queue_slot {
    char id[JOB_ID_LEN + 1];
} queue_slot;

struct job_queue {
    pthread_mutex_t mu;
    pthread_cond_t nonempty;
    queue_slot *slots;
    int capacity, head, count, limit;
    int closed;
};

job_queue *queue_create(int limit)
{
    if (limit < 1)
        return NULL;
    job_queue *q = calloc(1, sizeof *q);
    if (!q)
        return NULL;
    q->capacity = limit;
    q->limit = limit;
    q->slots = calloc((size_t)q->capacity, sizeof *q->slots);
    if (!q->slots) {
        free(q);
        return NULL;
    }
    pthread_mutex_init(&q->mu, NULL);
    pthread_cond_init(&q->nonempty, NULL);
    return q;
}

void queue_destroy(job_queue *q)
{
    if (!q)
        return;
    pthread_mutex_destroy(&q->mu);
    pthread_cond_destroy(&q->nonempty);
    free(q->slots);
    free(q);
}

static int grow(job_queue *q)
{
    int capacity = q->capacity * 2;
    queue_slot *slots = calloc((size_t)capacity, sizeof *slots);
    if (!slots)
        return -1;
    for (int i = 0; i < q->count; i++)
        slots[i] = q->slots[(q->head + i) % q->capacity];
    free(q->slots);
    q->slots = slots;
    q->capacity = capacity;
    q->head = 0;
    return 0;
}

int queue_push(job_queue *q, const char *id, int over_limit)
{
    pthread_mutex_lock(&q->mu);
    int rc = QUEUE_OK;
    if (q->closed)
        rc = QUEUE_CLOSED;
    else if (q->count >= q->limit && !over_limit)
        rc = QUEUE_FULL;
    else if (q->count == q->capacity && grow(q) != 0)
        rc = QUEUE_NOMEM;
    if (rc == QUEUE_OK) {
        queue_slot *slot = &q->slots[(q->head + q->count) % q->capacity];
        strncpy(slot->id, id, JOB_ID_LEN);
        slot->id[JOB_ID_LEN] = '\0';
        q->count++;
        pthread_cond_signal(&q->nonempty);
    }
    pthread_mutex_unlock(&q->mu);
    return rc;
}

int queue_pop(job_queue *q, char *id_out)
{
    pthread_mutex_lock(&q->mu);
    while (q->count == 0 && !q->closed)
        pthread_cond_wait(&q->nonempty, &q->mu);
    int rc = QUEUE_CLOSED;
    if (!q->closed) {
        memcpy(id_out, q->slots[q->head].id, JOB_ID_LEN + 1);
        q->head = (q->head + 1) % q->capacity;
        q->count--;
        rc = QUEUE_OK;
    }
    pthread_mutex_unlock(&q->mu);
    return rc;
}

int queue_remove(job_queue *q, const char *id)
{
    pthread_mutex_lock(&q->mu);
    int removed = 0;
    for (int i = 0; i < q->count && !removed; i++) {
        if (strcmp(q->slots[(q->head + i) % q->capacity].id, id) != 0)
            continue;
        for (int k = i; k + 1 < q->count; k++)
            q->slots[(q->head + k) % q->capacity] = q->slots[(q->head + k + 1) % q->capacity];
        q->count--;
        removed = 1;
    }
    pthread_mutex_unlock(&q->mu);
    return removed;
}

int queue_depth(job_queue *q)
{
    pthread_mutex_lock(&q->mu);
    int n = q->count;
    pthread_mutex_unlock(&q->mu);
    return n;
}

int queue_limit(const job_queue *q)
{
    return q->limit;
}

void queue_close(job_queue *q)
{
    pthread_mutex_lock(&q->mu);
    q->closed = 1;
    pthread_cond_broadcast(&q->nonempty);
    pthread_mutex_unlock(&q->mu);
}
