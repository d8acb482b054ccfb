/* queue.h - the queue of job ids waiting for a worker.
 *
 * DESIGN (after Redis bio.c). One queue, shared by the HTTP threads (producers) and the
 * worker threads (consumers). It owns only job ids, never job data: the job store
 * (store.h) owns jobs. Everything is guarded by one mutex; a condition variable wakes a
 * worker when an id arrives or when the queue is closed. A worker takes an id under the
 * lock and runs the job without it. The depth is read under the lock, so /metrics and the
 * 503 "queue full" answer see a consistent number. First in, first out. */
#ifndef TEXOPT_SERVER_QUEUE_H
#define TEXOPT_SERVER_QUEUE_H

#include <stddef.h>

#define JOB_ID_LEN 32 /* hex characters of a job id */

typedef struct job_queue job_queue;

/* A queue that accepts at most limit ids at once (push refuses beyond). NULL on failure. */
job_queue *queue_create(int limit);
void queue_destroy(job_queue *q); /* accepts NULL; the queue must have no waiting consumer */

enum { QUEUE_OK = 0, QUEUE_FULL = -1, QUEUE_CLOSED = -2, QUEUE_NOMEM = -3 };

/* Appends id. over_limit non-zero ignores the limit (jobs restored after a restart were
 * accepted once and must all run). Returns QUEUE_OK, QUEUE_FULL, QUEUE_CLOSED or QUEUE_NOMEM. */
int queue_push(job_queue *q, const char *id, int over_limit);

/* Waits for the oldest id and copies it to id_out (JOB_ID_LEN + 1 bytes). Returns QUEUE_OK,
 * or QUEUE_CLOSED once the queue is closed (ids still queued stay on disk as queued jobs). */
int queue_pop(job_queue *q, char *id_out);

/* Removes id if it is waiting (a canceled job). Returns 1 when it was removed, else 0. */
int queue_remove(job_queue *q, const char *id);

/* How many ids are waiting; the limit. */
int queue_depth(job_queue *q);
int queue_limit(const job_queue *q);

/* Wakes every waiting consumer with QUEUE_CLOSED and refuses further pushes. */
void queue_close(job_queue *q);

#endif
