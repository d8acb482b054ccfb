/* store_lease.c - the rules of job leases (see store_lease.h). */
#include "store_lease.h"

#include <stdio.h>
#include <string.h>

int lease_heartbeat_ms(int lease_seconds)
{
    int third = lease_seconds * 1000 / 3;
    return third < 1000 ? third : 1000;
}

job_state lease_expired_outcome(int attempts, int max_attempts, int cancel_requested)
{
    if (cancel_requested)
        return JOB_CANCELED;
    return attempts >= max_attempts ? JOB_FAILED : JOB_QUEUED;
}

void lease_exhausted_problem(int attempts, job_problem *out)
{
    memset(out, 0, sizeof *out);
    out->status = 500;
    snprintf(out->type, sizeof out->type, "urn:texopt:problem:attempts-exhausted");
    snprintf(out->title, sizeof out->title, "The job's runs kept stopping");
    snprintf(out->detail, sizeof out->detail,
             "the node running the job stopped answering %d time%s (its lease ran out); the job is not run "
             "again",
             attempts, attempts == 1 ? "" : "s");
}

int lease_lost(int found, int64_t leased_ms, int64_t heartbeat_started_ms)
{
    return !found && leased_ms < heartbeat_started_ms;
}
