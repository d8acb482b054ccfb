/* store_lease.h - the rules of job leases in a shared store (pure functions, unit-tested).
 *
 * A node that runs a job holds its lease: the row says which node and until when. The node
 * renews every lease it holds at each heartbeat; a node that stops (SIGKILL, power, network)
 * stops renewing, and once the lease has run out any node reaps the job: it runs again from
 * the start elsewhere, unless a cancel was asked (then it is canceled) or it already started
 * max_attempts runs (then it fails with the reason, instead of taking nodes down forever).
 * Does not: talk to the database (store_pg.c does). */
#ifndef TEXOPT_SERVER_STORE_LEASE_H
#define TEXOPT_SERVER_STORE_LEASE_H

#include <stddef.h>
#include <stdint.h>

#include "store.h"

/* Milliseconds between heartbeats: a third of the lease, so two may be late before the
 * lease runs out, and at most a second, which bounds how long a cancel takes to reach the
 * node running the job. */
int lease_heartbeat_ms(int lease_seconds);

/* What becomes of a running job whose lease ran out: JOB_QUEUED (run it again),
 * JOB_CANCELED or JOB_FAILED. */
job_state lease_expired_outcome(int attempts, int max_attempts, int cancel_requested);

/* The problem of a job failed by lease_expired_outcome. */
void lease_exhausted_problem(int attempts, job_problem *out);

/* Whether a running job that a heartbeat did not find leased to this node has lost its
 * lease: only when it was leased before that heartbeat began (a job leased meanwhile was not
 * there to be found). */
int lease_lost(int found, int64_t leased_ms, int64_t heartbeat_started_ms);

#endif
