/* head_watch.h - connections still sending their request head, and cutting the slow ones.
 *
 * Why: libmicrohttpd's connection timeout is an inactivity timeout, so a client that sends
 * one header byte every few seconds keeps a connection (and, thread per connection, a
 * thread) forever; 520 such sockets took every slot and /healthz timed out. Here every
 * connection is watched from accept until its request head (request line and headers) is
 * complete, and again between requests of a keep-alive connection. A head is cut (the
 * socket shut down, which ends its libmicrohttpd thread) when
 *   - it is not complete `timeout` seconds after it began (head_watch_sweep, each second);
 *   - its address already has `per_address` heads waiting: the oldest of them goes;
 *   - `total` heads are waiting: the oldest of all goes.
 * So heads that trickle can hold at most `total` slots, one address at most `per_address`,
 * and a request that sends its head at once (a health probe) always gets in. Does not:
 * limit a request whose head is complete (its body is the idle timeout's business).
 * Thread-safe (one mutex); the sockets are shut down under it, and libmicrohttpd closes a
 * socket only after head_watch_close (its CLOSED notification), so no descriptor is
 * reused under a cut. */
#ifndef TEXOPT_API_HEAD_WATCH_H
#define TEXOPT_API_HEAD_WATCH_H

#include <stddef.h>
#include <sys/socket.h>

typedef struct head_watch head_watch;
typedef struct head_entry head_entry;

/* NULL when out of memory. timeout in seconds; total and per_address >= 1. */
head_watch *head_watch_create(double timeout, int total, int per_address);
void head_watch_destroy(head_watch *hw); /* accepts NULL; every entry must be closed */

/* A connection accepted at `now` (monotonic seconds) on socket fd from addr: watched until
 * its head is complete; may cut older heads (see above). NULL when out of memory (the
 * connection is then not watched). */
head_entry *head_watch_open(head_watch *hw, int fd, const struct sockaddr *addr, double now);

/* Its head is complete / it waits for the next request's head (keep-alive) since now. */
void head_watch_done(head_watch *hw, head_entry *e);
void head_watch_again(head_watch *hw, head_entry *e, double now);

/* The connection closed: forgets and frees e (accepts NULL). */
void head_watch_close(head_watch *hw, head_entry *e);

/* Cuts every head older than the timeout at now. Returns how many were cut. */
int head_watch_sweep(head_watch *hw, double now);

/* Heads waiting now; heads cut so far. */
int head_watch_waiting(head_watch *hw);
long long head_watch_cut_count(head_watch *hw);

#endif
