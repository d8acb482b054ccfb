/* head_watch.c - the request-head deadline and caps (see head_watch.h). */
#include "head_watch.h"

#include <netinet/in.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

struct head_entry {
    head_entry *prev, *next; /* in the waiting list, oldest first, while waiting */
    int waiting;
    int fd;
    unsigned char address[16]; /* IPv4 or IPv6 address bytes (no port) */
    size_t address_len;
    double since;
};

struct head_watch {
    pthread_mutex_t mu;
    head_entry *oldest, *newest;
    int waiting;
    long long cut;
    double timeout;
    int total, per_address;
};

head_watch *head_watch_create(double timeout, int total, int per_address)
{
    head_watch *hw = calloc(1, sizeof *hw);
    if (!hw)
        return NULL;
    pthread_mutex_init(&hw->mu, NULL);
    hw->timeout = timeout;
    hw->total = total < 1 ? 1 : total;
    hw->per_address = per_address < 1 ? 1 : per_address;
    return hw;
}

void head_watch_destroy(head_watch *hw)
{
    if (!hw)
        return;
    pthread_mutex_destroy(&hw->mu);
    free(hw);
}

static void set_address(head_entry *e, const struct sockaddr *addr)
{
    e->address_len = 0;
    if (addr && addr->sa_family == AF_INET) {
        const struct sockaddr_in *v4 = (const struct sockaddr_in *)(const void *)addr;
        memcpy(e->address, &v4->sin_addr, 4);
        e->address_len = 4;
    } else if (addr && addr->sa_family == AF_INET6) {
        const struct sockaddr_in6 *v6 = (const struct sockaddr_in6 *)(const void *)addr;
        memcpy(e->address, &v6->sin6_addr, 16);
        e->address_len = 16;
    }
}

static int same_address(const head_entry *a, const head_entry *b)
{
    return a->address_len == b->address_len && memcmp(a->address, b->address, a->address_len) == 0;
}

/* The list operations: the caller holds mu. */
static void unlink_waiting(head_watch *hw, head_entry *e)
{
    if (!e->waiting)
        return;
    if (e->prev)
        e->prev->next = e->next;
    else
        hw->oldest = e->next;
    if (e->next)
        e->next->prev = e->prev;
    else
        hw->newest = e->prev;
    e->prev = e->next = NULL;
    e->waiting = 0;
    hw->waiting--;
}

static void append_waiting(head_watch *hw, head_entry *e, double now)
{
    unlink_waiting(hw, e);
    e->since = now;
    e->prev = hw->newest;
    e->next = NULL;
    if (hw->newest)
        hw->newest->next = e;
    else
        hw->oldest = e;
    hw->newest = e;
    e->waiting = 1;
    hw->waiting++;
}

/* Shuts the socket down: its thread's next read ends, and libmicrohttpd closes it. */
static void cut(head_watch *hw, head_entry *e)
{
    unlink_waiting(hw, e);
    shutdown(e->fd, SHUT_RDWR);
    hw->cut++;
}

/* Makes room for one more waiting head from e's address, and one more in all. */
static void apply_caps(head_watch *hw, const head_entry *e)
{
    int same = 0;
    head_entry *oldest_same = NULL;
    for (head_entry *w = hw->oldest; w; w = w->next)
        if (same_address(w, e)) {
            if (!oldest_same)
                oldest_same = w;
            same++;
        }
    if (oldest_same && same >= hw->per_address)
        cut(hw, oldest_same);
    if (hw->oldest && hw->waiting >= hw->total)
        cut(hw, hw->oldest);
}

head_entry *head_watch_open(head_watch *hw, int fd, const struct sockaddr *addr, double now)
{
    head_entry *e = calloc(1, sizeof *e);
    if (!e)
        return NULL;
    e->fd = fd;
    set_address(e, addr);
    pthread_mutex_lock(&hw->mu);
    apply_caps(hw, e);
    append_waiting(hw, e, now);
    pthread_mutex_unlock(&hw->mu);
    return e;
}

void head_watch_done(head_watch *hw, head_entry *e)
{
    if (!e)
        return;
    pthread_mutex_lock(&hw->mu);
    unlink_waiting(hw, e);
    pthread_mutex_unlock(&hw->mu);
}

void head_watch_again(head_watch *hw, head_entry *e, double now)
{
    if (!e)
        return;
    pthread_mutex_lock(&hw->mu);
    apply_caps(hw, e);
    append_waiting(hw, e, now);
    pthread_mutex_unlock(&hw->mu);
}

void head_watch_close(head_watch *hw, head_entry *e)
{
    if (!e)
        return;
    pthread_mutex_lock(&hw->mu);
    unlink_waiting(hw, e);
    pthread_mutex_unlock(&hw->mu);
    free(e);
}

int head_watch_sweep(head_watch *hw, double now)
{
    int n = 0;
    pthread_mutex_lock(&hw->mu);
    while (hw->oldest && now - hw->oldest->since >= hw->timeout) {
        cut(hw, hw->oldest);
        n++;
    }
    pthread_mutex_unlock(&hw->mu);
    return n;
}

int head_watch_waiting(head_watch *hw)
{
    pthread_mutex_lock(&hw->mu);
    int n = hw->waiting;
    pthread_mutex_unlock(&hw->mu);
    return n;
}

long long head_watch_cut_count(head_watch *hw)
{
    pthread_mutex_lock(&hw->mu);
    long long n = hw->cut;
    pthread_mutex_unlock(&hw->mu);
    return n;
}
