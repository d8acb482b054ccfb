/* test_queue.c - the job queue: FIFO order, the limit (and restored jobs past it), removal,
 * and consumers woken by push and by close. */
#define _DEFAULT_SOURCE
#include <pthread.h>
#include <string.h>
#include <unistd.h>

#include "queue.h"
#include "test.h"

static const char *id_of(int i)
{
    static char ids[8][JOB_ID_LEN + 1];
    memset(ids[i], 'a' + i, JOB_ID_LEN);
    ids[i][JOB_ID_LEN] = '\0';
    return ids[i];
}

TEST(fifo_with_limit_and_removal)
{
    job_queue *q = queue_create(3);
    CHECK(q != NULL);
    for (int i = 0; i < 3; i++)
        CHECK_EQ_INT(queue_push(q, id_of(i), 0), QUEUE_OK);
    CHECK_EQ_INT(queue_push(q, id_of(3), 0), QUEUE_FULL);
    CHECK_EQ_INT(queue_push(q, id_of(3), 1), QUEUE_OK); /* restored after a restart */
    CHECK_EQ_INT(queue_push(q, id_of(4), 1), QUEUE_OK); /* grows past the first capacity */
    CHECK_EQ_INT(queue_depth(q), 5);
    CHECK_EQ_INT(queue_remove(q, id_of(1)), 1);
    CHECK_EQ_INT(queue_remove(q, id_of(1)), 0);
    char got[JOB_ID_LEN + 1];
    int expected[] = {0, 2, 3, 4};
    for (int k = 0; k < 4; k++) {
        CHECK_EQ_INT(queue_pop(q, got), QUEUE_OK);
        CHECK(strcmp(got, id_of(expected[k])) == 0);
    }
    CHECK_EQ_INT(queue_depth(q), 0);
    queue_destroy(q);
}

typedef struct consumer {
    job_queue *q;
    int rc;
    char id[JOB_ID_LEN + 1];
} consumer;

static void *consume(void *arg)
{
    consumer *c = arg;
    c->rc = queue_pop(c->q, c->id);
    return NULL;
}

TEST(a_waiting_consumer_gets_the_pushed_id_then_close_wakes_the_rest)
{
    job_queue *q = queue_create(4);
    consumer a = {q, 99, ""}, b = {q, 99, ""};
    pthread_t ta, tb;
    pthread_create(&ta, NULL, consume, &a);
    pthread_create(&tb, NULL, consume, &b);
    usleep(20000);
    CHECK_EQ_INT(queue_push(q, id_of(5), 0), QUEUE_OK);
    usleep(20000);
    queue_close(q);
    pthread_join(ta, NULL);
    pthread_join(tb, NULL);
    int ok = (a.rc == QUEUE_OK) + (b.rc == QUEUE_OK);
    int closed = (a.rc == QUEUE_CLOSED) + (b.rc == QUEUE_CLOSED);
    CHECK_EQ_INT(ok, 1);
    CHECK_EQ_INT(closed, 1);
    CHECK(strcmp(a.rc == QUEUE_OK ? a.id : b.id, id_of(5)) == 0);
    CHECK_EQ_INT(queue_push(q, id_of(6), 0), QUEUE_CLOSED);
    queue_destroy(q);
}
