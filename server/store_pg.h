/* store_pg.h - the job store in PostgreSQL, shared by many texoptd nodes (issue 44).
 *
 * DESIGN. Jobs, their states, their latest event and their idempotency keys are rows of
 * texopt_jobs (store_pg_schema.h); uploads and results are files under a directory every
 * node mounts (--blob-dir), so any node answers any request about any job. A worker takes
 * the oldest queued job with SELECT ... FOR UPDATE SKIP LOCKED and holds a lease that a
 * per-node thread renews (store_lease.h): a node killed mid-job stops renewing, and after
 * the lease any node puts the job back in the queue (or fails it after --max-attempts
 * runs). A run writes its outputs into a directory of its own; finishing moves them into
 * the job directory (rename) inside the transaction that checks this node still holds the
 * lease and marks the job succeeded, so a job is published once even when a node that lost
 * its lease finishes late. Cancels are a column the owner's heartbeat reads.
 *
 * Waking: the same thread LISTENs on texopt_queue (a job was queued: idle workers try to
 * lease) and texopt_events (a job changed: event streams on every node re-read it); both
 * also wake on a timeout, so a lost notification only delays.
 * Unreachable database: operations fail with STORE_IO, store_unreachable() turns 1 (uploads
 * 503, /readyz 503) until a heartbeat succeeds again; running jobs keep running while
 * their lease lasts. Built only when libpq is found (TEXOPT_HAVE_POSTGRES). */
#ifndef TEXOPT_SERVER_STORE_PG_H
#define TEXOPT_SERVER_STORE_PG_H

#include <stddef.h>

#include "config.h"
#include "store.h"

/* Connects to config->store, creates or migrates the schema and starts the node thread.
 * NULL with a message when the database cannot be reached or its schema is newer. */
job_store *pg_store_open(const service_config *config, char *err, size_t err_len);

#endif
