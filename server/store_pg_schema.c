/* store_pg_schema.c - the shared store's migrations (see store_pg_schema.h). */
#include "store_pg_schema.h"

#include <stdio.h>

/* Columns: the accepted job as job.json (description: its id, files, params, key, sizes),
 * and what changes as it runs, each in a column of its own so that leasing, heartbeats and
 * progress are single UPDATEs. event_seq is the id of the job's latest event (server-sent
 * events). lease_owner/lease_until_ms: the node running it and until when (the database's
 * clock, in Unix ms). */
static const char *const migrations[] = {
    "CREATE TABLE texopt_jobs ("
    " id text PRIMARY KEY,"
    " created_ms bigint NOT NULL,"
    " idempotency_key text UNIQUE,"
    " description text NOT NULL,"
    " state text NOT NULL CHECK (state IN ('queued', 'running', 'succeeded', 'failed', 'canceled')),"
    " attempts integer NOT NULL DEFAULT 0,"
    " event_seq bigint NOT NULL DEFAULT 1,"
    " stage text NOT NULL DEFAULT '',"
    " progress double precision NOT NULL DEFAULT 0,"
    " eta_seconds double precision NOT NULL DEFAULT -1,"
    " mean_loss double precision NOT NULL DEFAULT 0,"
    " mean_area_scale double precision NOT NULL DEFAULT 0,"
    " started_ms bigint NOT NULL DEFAULT 0,"
    " finished_ms bigint NOT NULL DEFAULT 0,"
    " cancel_requested boolean NOT NULL DEFAULT false,"
    " has_report boolean NOT NULL DEFAULT false,"
    " problem_status integer NOT NULL DEFAULT 0,"
    " problem_type text NOT NULL DEFAULT '',"
    " problem_title text NOT NULL DEFAULT '',"
    " problem_detail text NOT NULL DEFAULT '',"
    " lease_owner text,"
    " lease_until_ms bigint NOT NULL DEFAULT 0);"
    "CREATE INDEX texopt_jobs_by_state ON texopt_jobs (state, created_ms, id);"
    "CREATE INDEX texopt_jobs_by_creation ON texopt_jobs (created_ms, id);"
    "CREATE INDEX texopt_jobs_by_owner ON texopt_jobs (lease_owner) WHERE lease_owner IS NOT NULL;",
};

int pg_schema_latest(void)
{
    return (int)(sizeof migrations / sizeof migrations[0]);
}

const char *pg_schema_migration(int version)
{
    return version >= 1 && version <= pg_schema_latest() ? migrations[version - 1] : NULL;
}

int pg_schema_plan(int current, int *first, char *err, size_t err_len)
{
    if (current < 0 || current > pg_schema_latest()) {
        snprintf(err, err_len,
                 "the database's texopt schema is version %d; this texoptd knows versions up to %d "
                 "(a newer texoptd made it: upgrade this node)",
                 current, pg_schema_latest());
        return -1;
    }
    *first = current + 1;
    return 0;
}
